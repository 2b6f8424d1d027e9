//! The render setup: how the world is looked at and sampled — camera, film parameters, pixel
//! filter, sampler and surface integrator, from the statements before `WorldBegin` — and
//! [`Renderable`], a [`World`] with its setup: everything a render session needs.
//!
//! ```text
//! SceneDescription --FilmParams / Camera / Filter / Sampler / Integrator::build--> RenderSetup
//!                  --World::build (told the integrator's light strategy)----------> World
//! ```
//!
//! The world never sees the setup's types: it is told what it needs ([`WorldOptions`]).

use super::extent::SampleExtent;
use crate::camera::{Camera, FilmGeometry};
use crate::fileio::SceneFiles;
use crate::film::{FilmError, FilmParams};
use crate::filter::Filter;
use crate::integrator::{Integrator, VolumeIntegrator};
use crate::lxs::{Diagnostic, Entity, Loc, SceneDescription};
use crate::plugin::{report_unused, warn, BuildError};
use crate::sampler::Sampler;
use crate::scene::{World, WorldOptions};

/// Why a scene could not be set up for rendering; every variant names the place in the scene
/// files.
#[derive(Debug, thiserror::Error)]
pub enum SetupError {
    #[error(transparent)]
    Film(#[from] FilmError),
    #[error(transparent)]
    Build(#[from] BuildError),
}

/// How the world is rendered: immutable once built, shared by the render threads.
pub struct RenderSetup {
    pub camera: Camera,
    pub film_params: FilmParams,
    pub filter: Filter,
    pub sampler: Sampler,
    pub integrator: Integrator,
}

impl RenderSetup {
    /// The film buffers this setup renders into (see [`super::buffers`]).
    pub fn buffers(&self) -> Vec<crate::film::BufferType> {
        super::buffers::buffers(self.sampler.per_screen(), self.integrator.splats())
    }

    /// The pixels eye samples are drawn over (see [`super::extent`]).
    pub fn sample_extent(&self) -> SampleExtent {
        SampleExtent::new(&self.film_params, &self.filter)
    }
}

/// A world with its render setup, and the problems that did not stop the build (unused
/// parameters, fallbacks), each located.
pub struct Renderable {
    pub world: World,
    pub setup: RenderSetup,
    pub warnings: Vec<Diagnostic>,
}

impl Renderable {
    /// Builds the setup, then the world; `files` opens the files the scene names: a
    /// directory (relative names resolve against it, as a local render does) or a
    /// [`SceneFiles`] confined to a bundle.
    pub fn build(
        desc: &SceneDescription,
        files: impl Into<SceneFiles>,
    ) -> Result<Renderable, SetupError> {
        let files = files.into();
        let mut warnings = Vec::new();
        let mut film_params = FilmParams::from_entity(desc.film.as_ref())?;
        if let Err(m) = film_params.tonemap.effects.load_response(&files) {
            let loc = desc
                .film
                .as_ref()
                .map(|f| f.loc.clone())
                .unwrap_or_default();
            return Err(BuildError::new(&loc, format!("Film \"cameraresponse\": {m}")).into());
        }
        let cam_desc = desc.camera.as_ref().ok_or_else(|| {
            BuildError::new(
                &Loc {
                    file: desc.root_file.as_str().into(),
                    line: 1,
                    col: 1,
                },
                "the scene has no Camera statement",
            )
        })?;
        let fg = FilmGeometry {
            xres: film_params.xres,
            yres: film_params.yres,
            crop: film_params.crop,
        };
        let mut camera = Camera::build_in(cam_desc, &fg, Some(&files), &mut warnings)?;
        let filter = Filter::build(desc.pixel_filter.as_ref(), &mut warnings)?;
        // Light paths reach the camera over the pixels eye samples cover.
        camera.set_sample_extent(SampleExtent::new(&film_params, &filter).bounds());
        let sampler = Sampler::build(desc.sampler.as_ref(), &mut warnings)?;
        let integrator = Integrator::build(desc.surface_integrator.as_ref(), &mut warnings)?;
        let volume = VolumeIntegrator::build(desc.volume_integrator.as_ref(), &mut warnings);
        let opts = WorldOptions {
            light_strategy: integrator.direct_settings().strategy,
            media: volume.renders_media(),
        };
        let world = World::build(desc, &files, opts, &mut warnings)?;
        let mut integrator = integrator;
        if integrator.splats() {
            if let Some(why) = world.lights().iter().find_map(|l| l.bidir_unsupported()) {
                let loc = desc
                    .surface_integrator
                    .as_ref()
                    .map(|e| e.loc.clone())
                    .unwrap_or_default();
                warn(
                    &mut warnings,
                    &loc,
                    format!(
                        "SurfaceIntegrator \"bidirectional\": light paths cannot start on {why} \
                         yet; rendering with \"path\""
                    ),
                );
                let path = Entity {
                    kind: "path".into(),
                    loc,
                    ..Default::default()
                };
                integrator = Integrator::build(Some(&path), &mut warnings)?;
            }
        }
        integrator.set_volume(volume);
        integrator.prepare(&world);
        if camera.needs_autofocus() {
            camera.autofocus(|r| world.intersect(r).map(|si| si.t));
        }
        warn_ignored(desc, &mut warnings);
        warn_zbuf_without_channel(desc, &film_params, &mut warnings);
        report_setup_unused(desc, &mut warnings);
        Ok(Renderable {
            world,
            setup: RenderSetup {
                camera,
                film_params,
                filter,
                sampler,
                integrator,
            },
            warnings,
        })
    }
}

/// `write_png_ZBuf` and `write_tga_ZBuf` ask for a channel those files do not have (LuxRender
/// 1.x's PNG and TGA writers ignore the flag): one located warning each.
fn warn_zbuf_without_channel(
    desc: &SceneDescription,
    params: &FilmParams,
    warnings: &mut Vec<Diagnostic>,
) {
    let Some(film) = &desc.film else {
        return;
    };
    for (fmt, out) in [("png", &params.png), ("tga", &params.tga)] {
        if out.enabled && out.zbuf {
            let name = format!("write_{fmt}_ZBuf");
            let loc = crate::texture::param_loc(&film.params, &name, &film.loc);
            warn(
                warnings,
                &loc,
                format!(
                    "Film \"{name}\": LuxRender writes a Z buffer only into the EXR output \
                     (write_exr_ZBuf); the {} file gets none",
                    fmt.to_uppercase()
                ),
            );
        }
    }
}

/// Statements luxfarm parses but does not render (region volumes) or has no use for (its own
/// BVH and renderer): one located warning each, saying what is ignored; their parameters go
/// through the unused-parameter report like every other statement's.
fn warn_ignored(desc: &SceneDescription, w: &mut Vec<Diagnostic>) {
    let options = [
        (
            "Accelerator",
            desc.accelerator.as_ref(),
            "luxfarm always builds its own BVH",
        ),
        (
            "Renderer",
            desc.renderer.as_ref(),
            "luxfarm always renders with its own CPU renderer",
        ),
    ];
    for (label, e, why) in options {
        if let Some(e) = e {
            warn(
                w,
                &e.loc,
                format!("{label} \"{}\" is ignored: {why}", e.kind),
            );
            report_unused(label, e, w);
        }
    }
    if let Some(e) = &desc.volume_integrator {
        report_unused("VolumeIntegrator", e, w);
    }
    crate::volume::warn_unrendered(desc, w);
}

/// Warns about parameters of the setup statements that no plugin read.
fn report_setup_unused(desc: &SceneDescription, w: &mut Vec<Diagnostic>) {
    let singles = [
        ("Camera", desc.camera.as_ref().map(|c| &c.entity)),
        ("Film", desc.film.as_ref()),
        ("PixelFilter", desc.pixel_filter.as_ref()),
        ("Sampler", desc.sampler.as_ref()),
        ("SurfaceIntegrator", desc.surface_integrator.as_ref()),
    ];
    for (label, e) in singles {
        if let Some(e) = e {
            report_unused(label, e, w);
        }
    }
}
