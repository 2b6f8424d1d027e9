//! Materials and their BSDFs (one file per material).
