//! Portals: window geometry through which a light at infinity (infinite, sky, sky2, the sky
//! half of sunsky/sunsky2) is sampled, as LuxRender 1.x's `PortalShape`/`PortalInstance`.
//!
//! Data flow: the scene build ([`crate::scene`]) turns the portal shapes tied to a
//! LightSource into world-space triangles and hands them to [`Portals::new`]; the light keeps
//! them, and [`super::Light::sample_li`] / [`super::Light::pdf_li`] then draw directions
//! through them instead of over the whole sphere, and [`super::Light::sample_le`] /
//! [`super::Light::line_density`] the lines light subpaths leave along (through a point drawn
//! on the portals, [`Portals::line_density`], instead of anywhere on the disc facing the
//! light).
//!
//! Sampling: a triangle is picked in proportion to its area and a point drawn uniformly on it,
//! so a point of the portals has area density 1/A (A the portals' total area). The direction
//! `wi` toward that point has solid-angle density Σ d²/(|cos θ| A) over *every* portal point
//! the ray `p + t·wi` (t > 0) crosses (portals may overlap or fold), which is also what
//! [`Portals::pdf`] answers for a direction found otherwise, so sampling and density agree.
//!
//! Unbiasedness: a light with portals draws a share [`PORTAL_SHARE`] of its directions
//! through them and the rest with its own sampling over the whole sphere, and answers the
//! mixture's density ([`mixture_pdf`]). Every direction the light shines from keeps a
//! positive density, so light sampling alone is unbiased even where no BSDF sample follows
//! (a path's last vertex, where light samples take the full weight), and where BSDF samples
//! do follow they are weighed against the mixture with the power heuristic. LuxRender 1.x
//! samples through the portals only (its Pdf is 0 elsewhere) and so loses light through
//! openings that no portal covers at a path's last vertex; the small share spent outside the
//! portals is what luxfarm pays instead. Portals are never rendered geometry.

use crate::sampling::DiscreteDistribution;
use glam::{Vec2, Vec3A};

/// Share of a portal light's samples drawn through its portals (the rest: its own sampling).
pub const PORTAL_SHARE: f32 = 0.9;

/// Density of the mixture: `portal` is [`Portals::pdf`], `own` the light's own density.
pub fn mixture_pdf(portal: f32, own: f32) -> f32 {
    PORTAL_SHARE * portal + (1.0 - PORTAL_SHARE) * own
}

/// Portal triangles at most (a window is a handful; the density test visits each).
pub const MAX_PORTAL_TRIANGLES: usize = 4096;

/// The world-space portal triangles of one light, with their area distribution.
#[derive(Clone, Debug)]
pub struct Portals {
    tris: Vec<[Vec3A; 3]>,
    pick: DiscreteDistribution,
    /// Total area A.
    area: f32,
    /// Bounding box of every triangle (a cheap miss test).
    lo: Vec3A,
    hi: Vec3A,
}

impl Portals {
    /// Portals over `tris` (world space); `None` when they have no area or are too many.
    pub fn new(tris: Vec<[Vec3A; 3]>) -> Result<Portals, String> {
        if tris.len() > MAX_PORTAL_TRIANGLES {
            return Err(format!(
                "{} portal triangles (at most {MAX_PORTAL_TRIANGLES} are sampled)",
                tris.len()
            ));
        }
        let tris: Vec<[Vec3A; 3]> = tris
            .into_iter()
            .filter(|t| t.iter().all(|v| v.is_finite()))
            .collect();
        let areas: Vec<f64> = tris.iter().map(|t| f64::from(tri_area(t))).collect();
        let pick = DiscreteDistribution::new(&areas)
            .ok_or_else(|| "the portal geometry has no area".to_string())?;
        let area = pick.total() as f32;
        if !(area > 0.0 && area.is_finite()) {
            return Err("the portal geometry has no area".into());
        }
        let (mut lo, mut hi) = (Vec3A::splat(f32::INFINITY), Vec3A::splat(f32::NEG_INFINITY));
        for v in tris.iter().flatten() {
            lo = lo.min(*v);
            hi = hi.max(*v);
        }
        Ok(Portals {
            tris,
            pick,
            area,
            lo,
            hi,
        })
    }

    pub fn triangle_count(&self) -> usize {
        self.tris.len()
    }

    /// Total portal area.
    pub fn area(&self) -> f32 {
        self.area
    }

    /// A point drawn uniformly by area on the portals (area density 1/A); `u_pick` chooses
    /// the triangle.
    pub fn sample_point(&self, u: Vec2, u_pick: f32) -> Option<Vec3A> {
        let i = self.pick.pick(u_pick);
        let [a, b, c] = *self.tris.get(i)?;
        let su = u.x.max(0.0).sqrt();
        let (b0, b1) = (1.0 - su, u.y * su);
        Some(a * b0 + b * b1 + c * (1.0 - b0 - b1))
    }

    /// A unit direction from `p` toward a point drawn uniformly by area on the portals, with
    /// its solid-angle density (see the module docs); `u_pick` chooses the triangle.
    pub fn sample(&self, p: Vec3A, u: Vec2, u_pick: f32) -> Option<(Vec3A, f32)> {
        let q = self.sample_point(u, u_pick)?;
        let wi = (q - p).normalize_or_zero();
        if wi == Vec3A::ZERO {
            return None;
        }
        let pdf = self.pdf(p, wi);
        (pdf > 0.0 && pdf.is_finite()).then_some((wi, pdf))
    }

    /// Solid-angle density with which [`Self::sample`] draws the unit direction `wi` from `p`.
    pub fn pdf(&self, p: Vec3A, wi: Vec3A) -> f32 {
        if !self.ray_meets_box(p, wi) {
            return 0.0;
        }
        let mut sum = 0.0f32;
        for t in &self.tris {
            if let Some((dist, cos)) = hit_triangle(p, wi, t) {
                if cos > 1e-7 {
                    sum += dist * dist / cos;
                }
            }
        }
        let pdf = sum / self.area;
        if pdf.is_finite() {
            pdf
        } else {
            0.0
        }
    }

    /// Density of the line through `p` along the unit direction `d`, per unit area of a plane
    /// perpendicular to `d`, when lines along `d` are drawn through a point picked uniformly
    /// on the portals: Σ 1/(A·|cos θ|) over every portal point on the whole line (a portal
    /// point's area maps to |cos θ| times that area across the line).
    pub fn line_density(&self, p: Vec3A, d: Vec3A) -> f32 {
        // Start behind every portal so that the whole line is ahead.
        let back = (p - (self.lo + self.hi) * 0.5).length() + (self.hi - self.lo).length() + 1.0;
        let start = p - d * back;
        if !self.ray_meets_box(start, d) {
            return 0.0;
        }
        let sum: f32 = self
            .tris
            .iter()
            .filter_map(|t| hit_triangle(start, d, t))
            .filter(|&(_, cos)| cos > 1e-7)
            .map(|(_, cos)| 1.0 / cos)
            .sum();
        let density = sum / self.area;
        if density.is_finite() {
            density
        } else {
            0.0
        }
    }

    /// Slab test of the ray `p + t·d` (t ≥ 0) against the portals' bounding box.
    fn ray_meets_box(&self, p: Vec3A, d: Vec3A) -> bool {
        let pad = (self.hi - self.lo).max_element() * 1e-4 + 1e-6;
        let (lo, hi) = (self.lo - Vec3A::splat(pad), self.hi + Vec3A::splat(pad));
        let (mut t0, mut t1) = (0.0f32, f32::INFINITY);
        for k in 0..3 {
            let (o, dk) = (p[k], d[k]);
            if dk.abs() < 1e-12 {
                if o < lo[k] || o > hi[k] {
                    return false;
                }
                continue;
            }
            let (a, b) = ((lo[k] - o) / dk, (hi[k] - o) / dk);
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
            if t0 > t1 {
                return false;
            }
        }
        true
    }
}

fn tri_area(t: &[Vec3A; 3]) -> f32 {
    0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length()
}

/// Distance along the unit direction `d` from `p` to triangle `t` (t > 0) and |cos| between
/// `d` and the triangle's normal (Möller–Trumbore).
fn hit_triangle(p: Vec3A, d: Vec3A, t: &[Vec3A; 3]) -> Option<(f32, f32)> {
    let e1 = t[1] - t[0];
    let e2 = t[2] - t[0];
    let pv = d.cross(e2);
    let det = e1.dot(pv);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let tv = p - t[0];
    let u = tv.dot(pv) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let qv = tv.cross(e1);
    let v = d.dot(qv) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let dist = e2.dot(qv) * inv;
    if dist <= 0.0 {
        return None;
    }
    let n = e1.cross(e2).normalize_or_zero();
    Some((dist, n.dot(d).abs()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_density_counts_every_portal_on_the_line() {
        // Two unit squares at z = 0 and z = 2: a vertical line through both crosses two
        // portal points, each of area density 1/2, at cos 1.
        let p = Portals::new([square(0.0), square(2.0)].concat()).unwrap();
        let down = Vec3A::new(0.0, 0.0, -1.0);
        assert!((p.line_density(Vec3A::new(0.3, 0.6, 1.0), down) - 1.0).abs() < 1e-5);
        // From below both, and from above: the whole line counts.
        assert!((p.line_density(Vec3A::new(0.3, 0.6, -5.0), down) - 1.0).abs() < 1e-5);
        assert!((p.line_density(Vec3A::new(0.3, 0.6, 7.0), -down) - 1.0).abs() < 1e-5);
        // A slanted line at 60° from the normal: 1/(A cos) per crossing.
        let d = Vec3A::new(3f32.sqrt() / 2.0, 0.0, -0.5);
        let got = p.line_density(Vec3A::new(0.2, 0.6, 0.0), d);
        assert!((got - 1.0 / (2.0 * 0.5)).abs() < 1e-4, "{got}");
        // Beside the portals: nothing.
        assert_eq!(p.line_density(Vec3A::new(3.0, 0.6, 1.0), down), 0.0);
    }

    /// A unit square [0,1]² in the plane z = `z`, two triangles.
    fn square(z: f32) -> Vec<[Vec3A; 3]> {
        let (a, b, c, d) = (
            Vec3A::new(0.0, 0.0, z),
            Vec3A::new(1.0, 0.0, z),
            Vec3A::new(1.0, 1.0, z),
            Vec3A::new(0.0, 1.0, z),
        );
        vec![[a, b, c], [a, c, d]]
    }

    #[test]
    fn density_straight_through_is_d2_over_area() {
        let p = Portals::new(square(2.0)).expect("portal");
        let pdf = p.pdf(Vec3A::new(0.3, 0.4, 0.0), Vec3A::Z);
        assert!((pdf - 4.0).abs() < 1e-4, "{pdf}");
        assert_eq!(p.pdf(Vec3A::new(0.3, 0.4, 0.0), -Vec3A::Z), 0.0);
        assert_eq!(p.pdf(Vec3A::new(3.0, 0.4, 0.0), Vec3A::Z), 0.0);
    }

    #[test]
    fn overlapping_portals_add_their_densities() {
        let mut tris = square(2.0);
        tris.extend(square(4.0));
        let p = Portals::new(tris).expect("portal");
        // A = 2: 2²/2 + 4²/2.
        let pdf = p.pdf(Vec3A::new(0.3, 0.6, 0.0), Vec3A::Z);
        assert!((pdf - 10.0).abs() < 1e-3, "{pdf}");
    }

    /// The density integrates to 1 over the directions through the portal: a Monte Carlo
    /// estimate of ∫ pdf dω with uniform sphere directions.
    #[test]
    fn density_integrates_to_one() {
        let p = Portals::new(square(0.5)).expect("portal");
        let o = Vec3A::new(0.2, 0.7, 0.0);
        let n = 400_000;
        let mut sum = 0.0f64;
        let mut rng = 0x2545_f491_u64;
        let mut next = || {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            (rng >> 40) as f32 / (1u64 << 24) as f32
        };
        for _ in 0..n {
            let w = crate::sampling::uniform_sphere(Vec2::new(next(), next()));
            sum += f64::from(p.pdf(o, w)) / f64::from(crate::sampling::UNIFORM_SPHERE_PDF);
        }
        let est = sum / n as f64;
        assert!((est - 1.0).abs() < 0.03, "∫pdf = {est}");
    }

    #[test]
    fn samples_go_through_the_portal_with_its_density() {
        let p = Portals::new(square(1.0)).expect("portal");
        let o = Vec3A::new(0.5, 0.5, 0.0);
        for i in 0..16 {
            let u = Vec2::new((i as f32 + 0.5) / 16.0, 0.37);
            let (wi, pdf) = p.sample(o, u, (i as f32) / 16.0).expect("sample");
            assert!(wi.z > 0.0);
            assert!((pdf - p.pdf(o, wi)).abs() <= 1e-5 * pdf);
        }
    }

    #[test]
    fn no_area_or_too_many_is_an_error() {
        let z = Vec3A::ZERO;
        assert!(Portals::new(vec![[z, z, z]]).is_err());
        assert!(Portals::new(Vec::new()).is_err());
        let many = vec![[z, Vec3A::X, Vec3A::Y]; MAX_PORTAL_TRIANGLES + 1];
        assert!(Portals::new(many).is_err());
    }
}
