//! IES photometric files (IESNA LM-63, the 1986, 1991, 1995 and 2002 variants): the text a
//! light's `iesname` names, read through the scene's files, parsed into an [`IesProfile`] —
//! candela values on a grid of vertical × horizontal angles — and evaluated in any direction
//! of the luminaire's own photometric frame.
//!
//! ```text
//! header lines ("IESNA:LM-63-2002", "[KEYWORD] ...") until "TILT=NONE"
//! lamps  lumens/lamp  candela-multiplier  #vertical  #horizontal  type  units  width length height
//! ballast-factor  ballast-lamp-photometric-factor  input-watts
//! #vertical angles, #horizontal angles, then #horizontal rows of #vertical candela values
//! ```
//!
//! Numbers are separated by blanks, commas or line ends. Only `TILT=NONE` is read (a tilt table
//! would give the output's change with the lamp's inclination; LuxRender ignores it too); other
//! tilts are refused with the line that states them. Every value is scaled by
//! candela-multiplier × ballast factor × ballast-lamp photometric factor, as LuxRender does.
//!
//! **Angles.** Type C (photometric type 1, the usual one): vertical angle V from the
//! luminaire's nadir axis, horizontal angle H around it. Files give only the part a symmetry
//! needs: one horizontal angle (rotationally symmetric), 0–90° (quadrant symmetric), 0–180°
//! (bilateral) or a full turn; the rest is unfolded. Vertical angles that stop short of 0° or
//! 180° emit nothing beyond them. Types B (2) and A (3): H and V are the angles left/right
//! and up/down of the beam axis (B: H about the luminaire's vertical axis, then V; A: V about
//! its lateral axis, then H), each from −90° to 90°; a profile giving only H ≥ 0 is symmetric
//! in H. Between tabulated angles the candela is interpolated linearly in both.
//!
//! Limits against hostile files: at most [`MAX_BYTES`] of text, [`MAX_ANGLES`] angles per axis
//! and [`MAX_VALUES`] candela values, every angle in its type's range and ascending, every
//! value finite and non-negative; counts are checked against the numbers present before
//! anything is allocated.

/// Largest IES file read.
pub const MAX_BYTES: usize = 4 << 20;
/// Most angles on one axis.
pub const MAX_ANGLES: usize = 10_000;
/// Most candela values.
pub const MAX_VALUES: usize = 1 << 20;

/// How the profile's angles relate to the luminaire (LM-63's photometric type).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PhotometricType {
    /// 1: vertical from nadir, horizontal around the vertical axis.
    C,
    /// 2: horizontal about the vertical axis, vertical above/below the beam.
    B,
    /// 3: vertical about the lateral axis, horizontal left/right of the beam.
    A,
}

/// A parsed IES profile.
#[derive(Clone, Debug)]
pub struct IesProfile {
    pub kind: PhotometricType,
    /// Vertical angles (degrees), ascending.
    pub vertical: Vec<f32>,
    /// Horizontal angles (degrees), ascending.
    pub horizontal: Vec<f32>,
    /// Scaled candela values, one row of `vertical.len()` per horizontal angle.
    pub candela: Vec<Vec<f32>>,
}

/// Numbers after the TILT line, each with its 1-based line.
struct Numbers {
    values: Vec<(f64, usize)>,
    next: usize,
    last_line: usize,
}

impl Numbers {
    fn take(&mut self, what: &str) -> Result<(f64, usize), String> {
        let v = self.values.get(self.next).copied().ok_or_else(|| {
            format!(
                "line {}: the file ends before the {what}",
                self.last_line.max(1)
            )
        })?;
        self.next += 1;
        Ok(v)
    }

    fn count(&mut self, what: &str) -> Result<usize, String> {
        let (v, line) = self.take(what)?;
        if !(v >= 1.0 && v <= MAX_ANGLES as f64 && v.fract() == 0.0) {
            return Err(format!(
                "line {line}: the {what} must be a whole number from 1 to {MAX_ANGLES} (got {v})"
            ));
        }
        Ok(v as usize)
    }

    fn remaining(&self) -> usize {
        self.values.len().saturating_sub(self.next)
    }
}

/// Splits the text after the TILT line into numbers, each with its line.
fn numbers(lines: &[&str], first_line: usize) -> Result<Numbers, String> {
    let mut values = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let n = first_line + i;
        for tok in line.split(|c: char| c.is_whitespace() || c == ',') {
            if tok.is_empty() {
                continue;
            }
            let v: f64 = tok
                .parse()
                .map_err(|_| format!("line {n}: \"{tok}\" is not a number"))?;
            if !v.is_finite() {
                return Err(format!("line {n}: {tok} is not a finite number"));
            }
            values.push((v, n));
        }
    }
    Ok(Numbers {
        values,
        next: 0,
        last_line: first_line + lines.len().saturating_sub(1),
    })
}

/// Reads `n` ascending angles within `lo..=hi` degrees.
fn angles(nums: &mut Numbers, n: usize, what: &str, lo: f64, hi: f64) -> Result<Vec<f32>, String> {
    let mut out: Vec<f32> = Vec::with_capacity(n);
    for _ in 0..n {
        let (a, line) = nums.take(what)?;
        if !(lo..=hi).contains(&a) {
            return Err(format!("line {line}: {what} {a}° is outside {lo}°..{hi}°"));
        }
        if out.last().is_some_and(|&p| f64::from(p) >= a) {
            return Err(format!("line {line}: {what} must ascend ({a}°)"));
        }
        out.push(a as f32);
    }
    Ok(out)
}

/// Parses the text of an IES file.
pub fn parse(text: &str) -> Result<IesProfile, String> {
    if text.len() > MAX_BYTES {
        return Err(format!("IES file larger than {MAX_BYTES} bytes"));
    }
    let lines: Vec<&str> = text.lines().collect();
    let tilt_at = lines
        .iter()
        .position(|l| l.trim_start().starts_with("TILT="))
        .ok_or("no TILT= line: not an IES (LM-63) file")?;
    let tilt = lines
        .get(tilt_at)
        .map(|l| l.trim()["TILT=".len()..].trim())
        .unwrap_or_default();
    if tilt != "NONE" {
        return Err(format!(
            "line {}: TILT={tilt} is not supported (only TILT=NONE)",
            tilt_at + 1
        ));
    }
    let mut nums = numbers(lines.get(tilt_at + 1..).unwrap_or_default(), tilt_at + 2)?;
    let _lamps = nums.take("number of lamps")?;
    let _lumens = nums.take("lumens per lamp")?;
    let (multiplier, _) = nums.take("candela multiplier")?;
    let nv = nums.count("number of vertical angles")?;
    let nh = nums.count("number of horizontal angles")?;
    let (kind_num, kind_line) = nums.take("photometric type")?;
    let kind = match kind_num as i64 {
        1 => PhotometricType::C,
        2 => PhotometricType::B,
        3 => PhotometricType::A,
        _ => {
            return Err(format!(
                "line {kind_line}: photometric type {kind_num} (1 = C, 2 = B, 3 = A)"
            ))
        }
    };
    for what in ["units type", "width", "length", "height"] {
        nums.take(what)?;
    }
    let (ballast, _) = nums.take("ballast factor")?;
    let (ballast_lamp, _) = nums.take("ballast-lamp photometric factor")?;
    let _watts = nums.take("input watts")?;
    if nv.saturating_mul(nh) > MAX_VALUES {
        return Err(format!(
            "{nv} × {nh} candela values: more than {MAX_VALUES}"
        ));
    }
    let needed = nv + nh + nv * nh;
    if nums.remaining() < needed {
        return Err(format!(
            "line {}: the file ends after {} of the {needed} angles and candela values",
            nums.last_line,
            nums.remaining()
        ));
    }
    let (vlo, hlo, hhi) = match kind {
        PhotometricType::C => (-90.0, -360.0, 360.0),
        PhotometricType::A | PhotometricType::B => (-90.0, -90.0, 90.0),
    };
    let vertical = angles(&mut nums, nv, "vertical angle", vlo, 180.0)?;
    let horizontal = angles(&mut nums, nh, "horizontal angle", hlo, hhi)?;
    let scale = multiplier * ballast * ballast_lamp;
    let mut candela = Vec::with_capacity(nh);
    for _ in 0..nh {
        let mut row = Vec::with_capacity(nv);
        for _ in 0..nv {
            let (c, line) = nums.take("candela value")?;
            let v = c * scale;
            if !(v >= 0.0 && v.is_finite() && v <= f64::from(f32::MAX)) {
                return Err(format!(
                    "line {line}: candela value {c} (× {scale}) is not usable"
                ));
            }
            row.push(v as f32);
        }
        candela.push(row);
    }
    Ok(IesProfile {
        kind,
        vertical,
        horizontal,
        candela,
    })
}

/// Linear interpolation in an ascending table: the bracketing index and weight of the upper
/// entry, or None outside it.
fn bracket(xs: &[f32], x: f32) -> Option<(usize, f32)> {
    let (first, last) = (*xs.first()?, *xs.last()?);
    if xs.len() == 1 {
        return ((x - first).abs() < 1e-4).then_some((0, 0.0));
    }
    if x < first || x > last {
        return None;
    }
    let hi = xs.partition_point(|&a| a < x).clamp(1, xs.len() - 1);
    let (a, b) = (xs[hi - 1], xs[hi]);
    Some((hi - 1, ((x - a) / (b - a)).clamp(0.0, 1.0)))
}

impl IesProfile {
    /// The candela of row `h` at vertical angle `v` (0 outside the tabulated range).
    fn row_at(&self, h: usize, v: f32) -> f32 {
        let Some(row) = self.candela.get(h) else {
            return 0.0;
        };
        match bracket(&self.vertical, v) {
            Some((i, w)) => {
                let a = row.get(i).copied().unwrap_or(0.0);
                let b = row.get(i + 1).copied().unwrap_or(a);
                a * (1.0 - w) + b * w
            }
            None => 0.0,
        }
    }

    /// Interpolated candela at horizontal angle `h` (already folded into the table's range)
    /// and vertical angle `v`.
    fn at(&self, h: f32, v: f32) -> f32 {
        if self.horizontal.len() == 1 {
            return self.row_at(0, v);
        }
        match bracket(&self.horizontal, h) {
            Some((i, w)) => self.row_at(i, v) * (1.0 - w) + self.row_at(i + 1, v) * w,
            None => 0.0,
        }
    }

    /// Folds a type C horizontal angle (degrees, any) into the table by its symmetry.
    fn fold_c(&self, h: f32) -> f32 {
        let first = self.horizontal.first().copied().unwrap_or(0.0);
        let last = self.horizontal.last().copied().unwrap_or(0.0);
        let h = h.rem_euclid(360.0);
        if first == 0.0 && last == 90.0 {
            let q = h.rem_euclid(180.0);
            return if q > 90.0 { 180.0 - q } else { q };
        }
        if first == 0.0 && last == 180.0 {
            return if h > 180.0 { 360.0 - h } else { h };
        }
        // A full turn (or a partial table): periodic from the first angle; beyond the last
        // angle [`Self::candela`] interpolates toward the first one a turn later.
        (h - first).rem_euclid(360.0) + first
    }

    /// Candela toward the unit direction `d` of the luminaire's frame: z is the type C nadir
    /// axis and the type A/B beam axis, x the direction of horizontal angle 0 (type C) and the
    /// lateral axis (types A and B), y the remaining one.
    pub fn candela(&self, d: [f32; 3]) -> f32 {
        let [x, y, z] = d;
        match self.kind {
            PhotometricType::C => {
                let mut v = z.clamp(-1.0, 1.0).acos().to_degrees();
                if self.vertical.first().is_some_and(|&a| a < 0.0) {
                    // Tables from −90° (horizon) up: LuxRender shifts them to start at nadir.
                    v -= 90.0;
                }
                let h = self.fold_c(y.atan2(x).to_degrees());
                let last = self.horizontal.last().copied().unwrap_or(0.0);
                let first = self.horizontal.first().copied().unwrap_or(0.0);
                if h > last && self.horizontal.len() > 1 {
                    // Wrap between the last angle and the first one a turn later.
                    let w = (h - last) / (first + 360.0 - last);
                    let n = self.horizontal.len() - 1;
                    return self.row_at(n, v) * (1.0 - w) + self.row_at(0, v) * w;
                }
                self.at(h, v)
            }
            PhotometricType::B => {
                if z <= 0.0 {
                    return 0.0;
                }
                let v = y.clamp(-1.0, 1.0).asin().to_degrees();
                let h = x.atan2(z).to_degrees();
                self.at(self.fold_ab(h), v)
            }
            PhotometricType::A => {
                if z <= 0.0 {
                    return 0.0;
                }
                let h = x.clamp(-1.0, 1.0).asin().to_degrees();
                let v = y.atan2(z).to_degrees();
                self.at(self.fold_ab(h), v)
            }
        }
    }

    /// Types A and B: a table of H ≥ 0 only is symmetric about the beam's vertical plane.
    fn fold_ab(&self, h: f32) -> f32 {
        if self.horizontal.first().is_some_and(|&a| a >= 0.0) {
            h.abs()
        } else {
            h
        }
    }

    /// The largest candela value in the table.
    pub fn max_candela(&self) -> f32 {
        self.candela.iter().flatten().fold(0.0f32, |m, &v| m.max(v))
    }
}

#[cfg(test)]
mod tests;
