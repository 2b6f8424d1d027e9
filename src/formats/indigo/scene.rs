//! Reading the top-level elements of an Indigo scene, in document order, into [`Scene`]:
//! everything converted to LuxRender terms and ready to be emitted.
//!
//! ```text
//! [Item] --dispatch on the element name-->
//!   renderer_settings, camera, tonemapping (first of each; later ones reported)
//!   medium, material (named and uid'd, referable by what follows)
//!   mesh, model, model2, sphere, meshlight, rectanglelight, exit_portal
//!   background, skylight, env_map, background_settings
//!   --> Scene
//! ```
//!
//! Both dialects are read: Indigo ≤ 2.x names meshes and materials (`model` with
//! `mesh_name`, mesh materials by name) and 3.x/4.x refers by `uid` (`model2` with
//! `geometry_uid` and `materials/material_uid`). A material's LuxRender name is its Indigo
//! name, made unique with its uid (or a counter) when two share a name.

use super::camera::{self, CameraOut};
use super::ctx::{err, Ctx};
use super::geometry::{self, Meshes, Model};
use super::lights::{self, AreaOut, LightOut};
use super::load::Item;
use super::material::{self, Lookup, MatOut};
use super::medium::{self, Medium};
use super::node::Elem;
use super::settings::{self, Exposure, Settings};
use crate::lxs::{Loc, LxsError, LxsErrorKind, ParamSet};
use glam::DMat4;
use std::collections::HashSet;

/// An analytic sphere.
#[derive(Debug)]
pub struct Sphere {
    pub center: [f64; 3],
    pub radius: f64,
    pub material: String,
    pub loc: Loc,
}

/// A light-emitting shape that is not a model (rectangle lights).
#[derive(Debug)]
pub struct AreaShape {
    pub params: ParamSet,
    pub area: AreaOut,
    pub loc: Loc,
}

/// A mesh light: a mesh placed, black, emitting.
#[derive(Debug)]
pub struct MeshLight {
    pub mesh: usize,
    pub keys: Vec<(f32, DMat4)>,
    pub area: AreaOut,
    pub loc: Loc,
}

/// An exit portal: a mesh placed, for light sampling only.
#[derive(Debug)]
pub struct Portal {
    pub mesh: usize,
    pub keys: Vec<(f32, DMat4)>,
    pub loc: Loc,
}

/// The whole scene in LuxRender terms.
pub struct Scene {
    pub settings: Settings,
    pub camera: Option<CameraOut>,
    pub media: Vec<Medium>,
    pub materials: Vec<MatOut>,
    pub meshes: Meshes,
    pub models: Vec<Model>,
    pub spheres: Vec<Sphere>,
    pub lights: Vec<LightOut>,
    pub area_shapes: Vec<AreaShape>,
    pub mesh_lights: Vec<MeshLight>,
    pub portals: Vec<Portal>,
    pub loc: Loc,
}

impl Scene {
    /// The light group of Indigo layer `i`.
    pub fn group(&self, i: i64) -> String {
        layer_group(&self.settings.layers, i)
    }
}

fn layer_group(layers: &[String], i: i64) -> String {
    usize::try_from(i)
        .ok()
        .and_then(|k| layers.get(k).cloned())
        .unwrap_or_else(|| {
            if i == 0 {
                "default".into()
            } else {
                format!("layer {i}")
            }
        })
}

/// Picks the first element of each single-valued kind; reports later ones.
fn first<'a>(items: &'a [Item], name: &str, ctx: &Ctx) -> Option<&'a Item> {
    let mut it = items.iter().filter(|i| i.elem.name == name);
    let f = it.next()?;
    for dup in it {
        dup.elem.mark_all_used();
        ctx.warn(
            &dup.elem.loc,
            format!(
                "a second <{name}> (the first is at {}): ignored",
                f.elem.loc
            ),
        );
    }
    Some(f)
}

/// Converts the loaded items; `stem` names the output images, `root` locates scene-wide
/// messages.
pub fn read(items: &[Item], stem: &str, root: &Loc, ctx: &Ctx) -> Result<Scene, LxsError> {
    let rs = first(items, "renderer_settings", ctx);
    let settings = settings::read(rs.map(|i| &i.elem), stem, ctx, root)?;
    let camera = match first(items, "camera", ctx) {
        Some(c) => Some(camera::read(&c.elem, settings.width, settings.height, ctx)?),
        None => None,
    };
    let mut scene = Scene {
        settings,
        camera,
        media: Vec::new(),
        materials: Vec::new(),
        meshes: Meshes::default(),
        models: Vec::new(),
        spheres: Vec::new(),
        lights: Vec::new(),
        area_shapes: Vec::new(),
        mesh_lights: Vec::new(),
        portals: Vec::new(),
        loc: root.clone(),
    };
    let exposure = scene.camera.as_ref().map_or(
        Exposure {
            duration: 1.0 / 30.0,
            fstop: 8.0,
        },
        |c| c.exposure,
    );
    let tm = first(items, "tonemapping", ctx);
    settings::tonemap(tm.map(|i| &i.elem), exposure, &mut scene.settings.film, ctx)?;

    let mut look = Lookup::default();
    look.media.insert("air".into(), Medium::air());
    let mut names: HashSet<String> = HashSet::new();
    for item in items {
        let (e, dir) = (&item.elem, item.dir.as_path());
        match e.name.as_str() {
            "renderer_settings" | "camera" | "tonemapping" => {}
            "medium" => {
                let m = medium::read(e, ctx)?;
                if let Some(u) = m.uid {
                    look.media_by_uid.insert(u, m.name.clone());
                }
                look.media.insert(m.name.clone(), m.clone());
                scene.media.push(m);
            }
            "material" => {
                let name = e.child_str(ctx, "name").unwrap_or("").to_string();
                let uid = e.child_int(ctx, "uid")?;
                let mut lux = if name.is_empty() {
                    "material".to_string()
                } else {
                    name.clone()
                };
                if names.contains(&lux) {
                    let base = lux.clone();
                    let mut k = 1;
                    lux = match uid {
                        Some(u) => format!("{base}#{u}"),
                        None => format!("{base}#{k}"),
                    };
                    while names.contains(&lux) {
                        k += 1;
                        lux = format!("{base}#{k}");
                    }
                    ctx.warn(&e.loc, format!("material name \"{base}\" is used twice: this one is \"{lux}\" in LuxRender, references by name use the first"));
                }
                let out = material::convert(e, &lux, dir, &look, ctx)?;
                names.insert(lux.clone());
                look.by_name.entry(name).or_insert_with(|| lux.clone());
                if let Some(u) = uid {
                    look.by_uid.insert(u, lux.clone());
                }
                scene.materials.push(out);
            }
            "mesh" => {
                let (m, uid) = geometry::read_mesh(e, dir, ctx)?;
                scene.meshes.add(m, uid, ctx);
            }
            "model" | "model2" => {
                let m = geometry::read_model(e, dir, &scene.meshes, &look, ctx)?;
                scene.models.push(m);
            }
            "sphere" => scene.spheres.push(sphere(e, &look, ctx)?),
            "background" => {
                let g = scene.group(0);
                scene.lights.push(lights::background(e, &g, ctx)?);
            }
            "skylight" => {
                let g = scene.group(0);
                scene.lights.push(lights::sunsky(e, &g, ctx)?);
            }
            "env_map" => {
                let g = scene.group(0);
                if let Some(l) = lights::env_map(e, dir, &g, ctx)? {
                    scene.lights.push(l);
                }
            }
            "background_settings" => {
                let layers = scene.settings.layers.clone();
                let group = move |i: i64| layer_group(&layers, i);
                if let Some(l) = lights::background_settings(e, dir, &group, ctx)? {
                    scene.lights.push(l);
                }
            }
            "rectanglelight" => {
                let g = scene.group(0);
                let (params, area) = lights::rectangle(e, &g, dir, ctx)?;
                scene.area_shapes.push(AreaShape {
                    params,
                    area,
                    loc: e.loc.clone(),
                });
            }
            "meshlight" => {
                e.mark_used();
                let mesh = mesh_ref(e, &scene.meshes, ctx)?;
                let keys = geometry::placement(e, ctx)?;
                let g = scene.group(e.child_int(ctx, "layer")?.unwrap_or(0));
                let area = lights::area_of(e, &g, dir, ctx)?;
                scene.mesh_lights.push(MeshLight {
                    mesh,
                    keys,
                    area,
                    loc: e.loc.clone(),
                });
            }
            "exit_portal" => {
                e.mark_used();
                let mesh = mesh_ref(e, &scene.meshes, ctx)?;
                let keys = geometry::placement(e, ctx)?;
                scene.portals.push(Portal {
                    mesh,
                    keys,
                    loc: e.loc.clone(),
                });
            }
            "metadata" => e.mark_all_used(),
            _ => {}
        }
    }
    Ok(scene)
}

fn mesh_ref(e: &Elem, meshes: &Meshes, ctx: &Ctx) -> Result<usize, LxsError> {
    let name = e.child_str(ctx, "mesh_name");
    let uid = e.child_int(ctx, "geometry_uid")?;
    let found = match (name, uid) {
        (_, Some(u)) => meshes.by_uid.get(&u),
        (Some(n), None) => meshes.by_name.get(n),
        _ => None,
    };
    found.copied().ok_or_else(|| {
        err(
            LxsErrorKind::Undefined,
            &e.loc,
            format!("<{}> names no mesh defined before it", e.name),
        )
    })
}

fn sphere(e: &Elem, look: &Lookup, ctx: &Ctx) -> Result<Sphere, LxsError> {
    e.mark_used();
    e.ignore(&["uid", "name"]);
    let center = e.need(ctx, "center")?.vec3(ctx)?;
    let radius = e.need(ctx, "radius")?.positive(ctx)?;
    let material = look.material(
        e.child_str(ctx, "material_name"),
        e.child_int(ctx, "material_uid")?,
        &e.loc,
    )?;
    Ok(Sphere {
        center,
        radius,
        material,
        loc: e.loc.clone(),
    })
}
