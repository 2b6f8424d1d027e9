//! The LightWave importer from file to description: read the scene, load its objects,
//! evaluate everything at the chosen frame, map it to LuxRender and emit it.
//!
//! ```text
//! .lws --scene::read--> Scene --library::load--> Models
//!   frame (ParseOptions::frame, else CurrentFrame, else FirstFrame) --> time = frame / fps
//!   --motion::evaluate (at the frame, and at the end of the shutter with motion blur)-->
//!   placements --camera.rs, lights.rs, material.rs, mesh.rs--> World --emit.rs--> description
//! ```

use super::emit::{self, Geometry, Placed, SurfaceMesh, World};
use super::items::{id_type, Scene, TYPE_OBJECT};
use super::library::{self, Library};
use super::material::{self, SurfacePlan};
use super::mesh::{self, UvSource};
use super::model::{Layer, Projection, Surface};
use super::motion::{self, Placement};
use super::paths::{read_within, Resolver};
use super::{camera, lights, scene};
use crate::lxs::{Diagnostic, Loc, LxsError, LxsErrorKind, ParseOptions, SceneDescription};
use glam::DVec3;
use std::collections::{BTreeMap, HashMap};
use std::path::Path;

/// Imports the .lws at `path` at the frame `opts` asks for.
pub fn load(path: &Path, opts: &ParseOptions) -> Result<SceneDescription, LxsError> {
    let file = path.to_string_lossy().into_owned();
    let file_loc = Loc {
        file: file.as_str().into(),
        line: 0,
        col: 0,
    };
    let mut budget = opts.max_total_bytes;
    let bytes = read_within(path, &mut budget, &file_loc)?;
    let text = decode(&bytes);
    let parsed = scene::read(&file, &text)?;
    let scene = parsed.scene;
    let mut warnings = parsed.warnings;
    let resolver = Resolver::new(path, opts.confine_to_root);
    let lib = library::load(&scene, &resolver, &mut budget, &mut warnings)?;
    let g = &scene.globals;
    let frame = opts.frame.or(g.current_frame).unwrap_or(g.first_frame);
    let time = scene.frame_time(frame);

    let cam_index = match &g.current_camera {
        Some((i, loc)) => usize::try_from(*i)
            .ok()
            .filter(|&i| i < scene.cameras.len())
            .ok_or_else(|| {
                LxsError::new(
                    LxsErrorKind::Undefined,
                    loc.clone(),
                    format!(
                        "CurrentCamera {i}: the scene has {} camera(s)",
                        scene.cameras.len()
                    ),
                )
            })?,
        None => 0,
    };
    let Some(cam) = scene.cameras.get(cam_index) else {
        return Err(LxsError::new(
            LxsErrorKind::Undefined,
            file_loc,
            "the scene has no camera (AddCamera)",
        ));
    };
    // Shutter times: the frame, and the end of the blur interval with motion blur.
    let (blur_on, blur_len) = if cam.use_global_blur {
        (g.global_motion_blur != 0, g.global_blur_length.at(time))
    } else {
        (cam.motion_blur != 0, cam.blur_length.at(time))
    };
    let mut times = vec![(0.0f32, time)];
    if blur_on && blur_len > 0.0 && blur_len.is_finite() {
        times.push((1.0, time + blur_len / g.fps));
    }
    let pivot_of = |id: u32| layer_pivot(&scene, &lib, id);
    let placements: Vec<HashMap<u32, Placement>> = times
        .iter()
        .map(|(_, t)| motion::evaluate(&scene, *t, &pivot_of))
        .collect::<Result<_, _>>()?;
    let at = |k: usize, id: u32| placements[k].get(&id).copied();

    let frames: Vec<_> = times
        .iter()
        .enumerate()
        .filter_map(|(k, (s, _))| at(k, cam.common.id).map(|p| (*s, p.frame)))
        .collect();
    let stem = path
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("lightwave");
    let cam_out = camera::setup(cam, g, time, &frames, &format!("{stem}_{frame:04}"));
    let mut located: Vec<(Loc, String)> = cam_out.warnings.clone();

    let mut light_list = Vec::new();
    for l in &scene.lights {
        if let Some(p) = at(0, l.common.id) {
            if let Some(out) =
                lights::light(l, &p.frame, time, g.double_sided_area_lights, &mut located)
            {
                light_list.push((l.common.loc.clone(), out));
            }
        }
    }
    let environment = lights::environment(g, time, &file_loc, &mut located);
    let objects = Objects::build(
        &scene,
        &lib,
        &resolver,
        &placements,
        &times,
        time,
        &mut warnings,
    );
    warnings.extend(
        located
            .into_iter()
            .map(|(loc, message)| Diagnostic { loc, message }),
    );
    let world = World {
        root_file: &file,
        camera: cam_out,
        camera_loc: cam.common.loc.clone(),
        integrator: emit::integrator(g.radiosity, g.ray_recursion_limit),
        environment,
        lights: light_list,
        plans: objects.plans,
        geometries: objects.geometries,
        placed: objects.placed,
        files: lib
            .models
            .iter()
            .map(|m| m.found.display.to_string_lossy().into_owned())
            .collect(),
        max_array_len: opts.max_array_len,
    };
    emit::emit(world, warnings)
}

/// Scene text: UTF-8, or Latin-1 (older LightWave versions write the system code page).
fn decode(bytes: &[u8]) -> String {
    match std::str::from_utf8(bytes) {
        Ok(s) => s.to_string(),
        Err(_) => bytes.iter().map(|&b| char::from(b)).collect(),
    }
}

/// The pivot of an object item from its (first) layer; zero for other items.
fn layer_pivot(scene: &Scene, lib: &Library, id: u32) -> DVec3 {
    if id_type(id) != TYPE_OBJECT {
        return DVec3::ZERO;
    }
    let Some(i) = scene.objects.iter().position(|o| o.common.id == id) else {
        return DVec3::ZERO;
    };
    let Some(Some((m, layers))) = lib.items.get(i) else {
        return DVec3::ZERO;
    };
    layers
        .first()
        .and_then(|&l| lib.models.get(*m)?.model.layers.get(l))
        .map_or(DVec3::ZERO, |l| DVec3::from(l.pivot.map(f64::from)))
}

/// Surfaces, meshes and placements of the visible objects.
struct Objects {
    plans: Vec<(Loc, SurfacePlan)>,
    geometries: Vec<Geometry>,
    placed: Vec<Placed>,
}

struct Builder<'a> {
    lib: &'a Library,
    resolver: &'a Resolver,
    plans: Vec<(Loc, SurfacePlan)>,
    plan_index: HashMap<(usize, Option<u32>), usize>,
    geometries: Vec<Geometry>,
    geo_index: HashMap<(usize, Vec<usize>), usize>,
    warnings: &'a mut Vec<Diagnostic>,
}

impl Objects {
    fn build(
        scene: &Scene,
        lib: &Library,
        resolver: &Resolver,
        placements: &[HashMap<u32, Placement>],
        times: &[(f32, f64)],
        time: f64,
        warnings: &mut Vec<Diagnostic>,
    ) -> Objects {
        let mut placed = Vec::new();
        let mut b = Builder {
            lib,
            resolver,
            plans: Vec::new(),
            plan_index: HashMap::new(),
            geometries: Vec::new(),
            geo_index: HashMap::new(),
            warnings,
        };
        let mut warned_rays = false;
        for (i, o) in scene.objects.iter().enumerate() {
            let Some(Some((m, layers))) = lib.items.get(i) else {
                continue;
            };
            let dissolve = o.dissolve.at(time).clamp(0.0, 1.0) as f32;
            if o.unseen_by_camera || dissolve >= 1.0 {
                continue;
            }
            if o.unseen_by_rays && !warned_rays {
                warned_rays = true;
                b.warnings.push(Diagnostic {
                    loc: o.common.loc.clone(),
                    message:
                        "UnseenByRays: the object is rendered in reflections and refractions too"
                            .into(),
                });
            }
            let geometry = b.geometry(*m, layers);
            let transforms = times
                .iter()
                .enumerate()
                .filter_map(|(k, (s, _))| placements[k].get(&o.common.id).map(|p| (*s, p.world)))
                .collect();
            placed.push(Placed {
                geometry,
                loc: o.common.loc.clone(),
                transforms,
                dissolve,
            });
        }
        Objects {
            plans: b.plans,
            geometries: b.geometries,
            placed,
        }
    }
}

impl Builder<'_> {
    fn warn(&mut self, loc: Loc, message: String) {
        if !self
            .warnings
            .iter()
            .any(|w| w.loc == loc && w.message == message)
        {
            self.warnings.push(Diagnostic { loc, message });
        }
    }

    fn model_loc(&self, m: usize) -> Loc {
        let file = self.lib.models[m]
            .found
            .display
            .to_string_lossy()
            .into_owned();
        Loc {
            file: file.as_str().into(),
            line: 0,
            col: 0,
        }
    }

    /// The surface polygons with tag `tag` use (LightWave's default when undefined).
    fn surface(&mut self, m: usize, tag: Option<u32>) -> Surface {
        let model = &self.lib.models[m].model;
        if let Some(s) = model.surface_for_tag(tag) {
            return s.clone();
        }
        let name = tag
            .and_then(|t| model.tags.get(t as usize))
            .cloned()
            .unwrap_or_else(|| "(untagged)".into());
        let loc = self.model_loc(m);
        self.warn(loc, format!("polygons use surface \"{name}\", which the object does not define: LightWave's default surface is used"));
        Surface::default_named(&name)
    }

    fn plan(&mut self, m: usize, tag: Option<u32>) -> usize {
        if let Some(&i) = self.plan_index.get(&(m, tag)) {
            return i;
        }
        let s = self.surface(m, tag);
        let model = &self.lib.models[m].model;
        let resolver = self.resolver;
        let object_dir = self.lib.models[m]
            .found
            .canonical
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default();
        let mut image = |blk: &super::model::TexBlock| -> Result<String, String> {
            let written = match (&blk.image_file, blk.clip) {
                (Some(f), _) => f.clone(),
                (None, Some(c)) => model
                    .clip(c)
                    .map(|c| c.file.clone())
                    .ok_or_else(|| format!("clip {c} is not defined"))?,
                (None, None) => return Err("no image is set".into()),
            };
            resolver
                .find_near(&written, &object_dir)
                .map(|f| f.from_scene.to_string_lossy().into_owned())
                .ok_or_else(|| format!("image \"{written}\" not found"))
        };
        let prefix = match tag {
            Some(_) => format!("lw{m}:{}", s.name),
            None => format!("lw{m}:(untagged)"),
        };
        let plan = material::plan(&s, &prefix, &mut image);
        let loc = self.model_loc(m);
        for w in &plan.warnings {
            self.warn(loc.clone(), w.clone());
        }
        self.plans.push((loc, plan));
        let i = self.plans.len() - 1;
        self.plan_index.insert((m, tag), i);
        i
    }

    fn geometry(&mut self, m: usize, layers: &[usize]) -> usize {
        if let Some(&i) = self.geo_index.get(&(m, layers.to_vec())) {
            return i;
        }
        let lib = self.lib;
        let model = &lib.models[m].model;
        let mut meshes = Vec::new();
        for &li in layers {
            let Some(layer) = model.layers.get(li) else {
                continue;
            };
            let mut groups: BTreeMap<Option<u32>, Vec<usize>> = BTreeMap::new();
            for (pi, p) in layer.polygons.iter().enumerate() {
                groups.entry(p.surface_tag).or_default().push(pi);
            }
            for (tag, polys) in groups {
                let plan = self.plan(m, tag);
                let s = self.surface(m, tag);
                let (uv, uv_warning) = uv_source(layer, &s, self.plans[plan].1.uv_block);
                if let Some(w) = uv_warning {
                    let loc = self.model_loc(m);
                    self.warn(loc, w);
                }
                let normals = s.normal_map.as_deref().and_then(|n| layer.normal_map(n));
                let mesh = mesh::build(layer, &polys, s.smoothing, normals, uv);
                if mesh.skipped > 0 {
                    let loc = self.model_loc(m);
                    self.warn(
                        loc,
                        format!(
                            "surface \"{}\": {} point or line polygons are not rendered",
                            s.name, mesh.skipped
                        ),
                    );
                }
                if !mesh.indices.is_empty() {
                    meshes.push(SurfaceMesh { mesh, plan });
                }
            }
        }
        let loaded = &lib.models[m];
        let layer_names: Vec<String> = layers.iter().map(|l| l.to_string()).collect();
        self.geometries.push(Geometry {
            name: format!(
                "lw:{}#{}",
                loaded.found.display.display(),
                layer_names.join(",")
            ),
            file_loc: self.model_loc(m),
            meshes,
        });
        let i = self.geometries.len() - 1;
        self.geo_index.insert((m, layers.to_vec()), i);
        i
    }
}

/// The texture coordinates a surface's image layer needs on `layer`, and a warning when its
/// UV map is missing.
fn uv_source<'a>(
    layer: &'a Layer,
    s: &'a Surface,
    uv_block: Option<usize>,
) -> (UvSource<'a>, Option<String>) {
    let Some(b) = uv_block.and_then(|i| s.blocks.get(i)) else {
        return (UvSource::None, None);
    };
    if b.projection != Projection::Uv {
        return (UvSource::Projected(b), None);
    }
    let wanted = b.uv_map.as_deref().unwrap_or("");
    if let Some(map) = layer.uv_map(wanted) {
        return (UvSource::Map(map), None);
    }
    match layer.uv_maps.first() {
        Some(first) => (
            UvSource::Map(first),
            Some(format!(
                "surface \"{}\": UV map \"{wanted}\" is not on this layer: \"{}\" is used",
                s.name, first.name
            )),
        ),
        None => (
            UvSource::None,
            Some(format!(
                "surface \"{}\": UV map \"{wanted}\" is not on this layer: the image is not mapped",
                s.name
            )),
        ),
    }
}
