//! Which film buffers a render fills, and how contributions that are not at their sample's
//! own pixel reach them.
//!
//! LuxRender's films hold one buffer per kind of contribution (per light group each):
//! - "eye": what camera samples see at their own film position: normalised per pixel
//!   (weighted mean), except with the Metropolis and ERPT samplers, whose sample density
//!   follows the image: normalised per screen (sums × pixels / samples);
//! - "light": what light subpaths bring to the camera (bidirectional), at film positions of
//!   their own: always per screen.
//!
//! [`film_buffers`] answers from the scene's statements alone, so the master creates the
//! same film layout as its workers without building the world. [`apply_splats`] adds
//! contributions at arbitrary film positions through the pixel filter.

use crate::film::{BufferType, Film};
use crate::filter::Filter;
use crate::integrator::Splat;
use crate::lxs::SceneDescription;
use crate::spectrum::rgb_to_xyz;

/// Index of the "light" buffer when a film has one.
pub const LIGHT_BUFFER: usize = 1;

/// The buffers for an eye buffer of this normalisation, with or without a light buffer.
pub fn buffers(per_screen_eye: bool, light: bool) -> Vec<BufferType> {
    let eye = if per_screen_eye {
        BufferType::PerScreen
    } else {
        BufferType::PerPixel
    };
    if light {
        vec![eye, BufferType::PerScreen]
    } else {
        vec![eye]
    }
}

/// The film buffers a scene renders into, from its SurfaceIntegrator statement (no
/// statement: path) and Sampler statement: the eye buffer is per screen with the
/// `metropolis` and `erpt` samplers.
pub fn film_buffers(desc: &SceneDescription) -> Vec<BufferType> {
    let integrator = desc.surface_integrator.as_ref().map(|e| e.kind.as_str());
    let sampler = desc.sampler.as_ref().map(|e| e.kind.as_str());
    buffers(
        matches!(sampler, Some("metropolis" | "erpt")),
        integrator == Some("bidirectional"),
    )
}

/// Adds splats to `buffer` of `film` (whose pixel (0, 0) is raster pixel `origin`) through
/// the filter, each splat's value scaled by `scale`; returns how many were rejected
/// (non-finite or negative luminance).
pub fn apply_splats(
    film: &mut Film,
    buffer: usize,
    filter: &Filter,
    origin: [u32; 2],
    splats: &[Splat],
    scale: f32,
) -> u64 {
    let (ox, oy) = (i64::from(origin[0]), i64::from(origin[1]));
    let mut rejected = 0;
    for sp in splats {
        let xyz = rgb_to_xyz(sp.l * scale);
        if !xyz.iter().all(|v| v.is_finite()) || xyz[1] < 0.0 {
            rejected += 1;
            continue;
        }
        let g = sp.group as usize;
        filter.splat(sp.p_film, |x, y, w| {
            let (lx, ly) = (i64::from(x) - ox, i64::from(y) - oy);
            if lx >= 0 && ly >= 0 && lx <= i64::from(u32::MAX) && ly <= i64::from(u32::MAX) {
                film.add_buffer_splat(g, buffer, lx as u32, ly as u32, xyz, 1.0, w);
                film.add_variance(lx as u32, ly as u32, xyz[1], w);
            }
        });
    }
    rejected
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::filter::FilterKind;
    use crate::lxs::{parse_str, ParseOptions};
    use crate::spectrum::Rgb;
    use glam::Vec2;

    fn layout(head: &str) -> Vec<BufferType> {
        let text = format!("{head}\nWorldBegin\nWorldEnd\n");
        film_buffers(&parse_str(&text, "t.lxs", &ParseOptions::default()).unwrap())
    }

    #[test]
    fn layouts_follow_sampler_and_integrator() {
        use BufferType::*;
        assert_eq!(layout(""), vec![PerPixel]);
        assert_eq!(
            layout("SurfaceIntegrator \"bidirectional\""),
            vec![PerPixel, PerScreen]
        );
        assert_eq!(layout("Sampler \"metropolis\""), vec![PerScreen]);
        assert_eq!(
            layout("Sampler \"metropolis\"\nSurfaceIntegrator \"bidirectional\""),
            vec![PerScreen, PerScreen]
        );
        assert_eq!(layout("Sampler \"erpt\""), vec![PerScreen]);
        assert_eq!(
            layout("Sampler \"erpt\"\nSurfaceIntegrator \"bidirectional\""),
            vec![PerScreen, PerScreen]
        );
    }

    #[test]
    fn splats_go_through_the_filter_into_the_buffer() {
        let mut film = Film::with_buffers(4, 4, vec![], buffers(false, true)).unwrap();
        let filter = Filter::new(FilterKind::Box, Vec2::splat(0.5));
        let splats = [
            Splat {
                p_film: Vec2::new(3.5, 2.5),
                group: 0,
                l: Rgb::splat(2.0),
                weight: 1.0,
            },
            Splat {
                p_film: Vec2::new(3.5, 2.5),
                group: 0,
                l: Rgb::new(f32::NAN, 0.0, 0.0),
                weight: 1.0,
            },
        ];
        // Film pixel (0, 0) is raster (2, 1): the splat lands on film pixel (1, 1).
        let rejected = apply_splats(&mut film, LIGHT_BUFFER, &filter, [2, 1], &splats, 0.5);
        assert_eq!(rejected, 1);
        let p = film.pixel(0, LIGHT_BUFFER, 1, 1).unwrap();
        assert!(
            (p[1] - f64::from(rgb_to_xyz(Rgb::WHITE)[1])).abs() < 1e-6,
            "{p:?}"
        );
        assert_eq!(film.pixel(0, 0, 1, 1), Some([0.0; 5]));
    }
}
