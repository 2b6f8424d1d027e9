//! Samplers: random, lowdiscrepancy, sobol; every value derived from (seed, stream, pixel, sample).
