//! Pixel filters: box, gaussian, mitchell, triangle, sinc, catmullrom, blackmanharris.
