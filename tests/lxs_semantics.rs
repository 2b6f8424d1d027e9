//! Graphics-state semantics: scoping, transforms, motion, objects and instances, named
//! coordinate systems, light groups, volumes, legacy names, and a builder other than the
//! description builder.

use glam::{DMat4, DVec3};
use luxfarm::lxs::{
    self, Diagnostic, Entity, Loc, LxsResult, ParamSet, ParseOptions, SceneBuilder,
};

fn parse(text: &str) -> lxs::SceneDescription {
    lxs::parse_str(text, "t.lxs", &ParseOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn origin(m: DMat4) -> DVec3 {
    m.transform_point3(DVec3::ZERO)
}

#[test]
fn transform_begin_scopes_only_the_ctm_attribute_begin_scopes_state() {
    let d = parse(
        "WorldBegin\n\
         Material \"matte\"\n\
         TransformBegin\n Translate 1 0 0\n Material \"glass\"\nTransformEnd\n\
         Shape \"sphere\"\n\
         AttributeBegin\n Material \"metal\" \n ReverseOrientation\nAttributeEnd\n\
         Shape \"sphere\"\n\
         WorldEnd\n",
    );
    assert_eq!(d.shapes.len(), 2);
    // The glass material survives TransformEnd; the metal one does not survive AttributeEnd.
    assert_eq!(
        d.materials[d.shapes[0].material.unwrap()].entity.kind,
        "glass"
    );
    assert_eq!(
        d.materials[d.shapes[1].material.unwrap()].entity.kind,
        "glass"
    );
    assert_eq!(origin(d.shapes[0].object_to_world.start()), DVec3::ZERO);
    assert!(!d.shapes[1].reverse_orientation);
}

#[test]
fn transforms_post_multiply_and_transform_takes_columns() {
    let d = parse(
        "WorldBegin\nTranslate 1 2 3\nScale 2 2 2\nShape \"sphere\"\n\
         Transform [1 0 0 0  0 1 0 0  0 0 1 0  5 6 7 1]\nShape \"sphere\"\n\
         ConcatTransform [0 1 0 0  -1 0 0 0  0 0 1 0  0 0 0 1]\nShape \"sphere\"\n\
         Identity\nRotate 90 0 0 1\nShape \"sphere\"\nWorldEnd\n",
    );
    let m0 = d.shapes[0].object_to_world.start();
    assert_eq!(m0.transform_point3(DVec3::X), DVec3::new(3.0, 2.0, 3.0));
    assert_eq!(
        origin(d.shapes[1].object_to_world.start()),
        DVec3::new(5.0, 6.0, 7.0)
    );
    let m2 = d.shapes[2].object_to_world.start();
    assert_eq!(m2.transform_point3(DVec3::X), DVec3::new(5.0, 7.0, 7.0));
    let m3 = d.shapes[3].object_to_world.start();
    assert!((m3.transform_point3(DVec3::X) - DVec3::Y).length() < 1e-12);
}

#[test]
fn camera_coordinate_systems() {
    let d = parse(
        "Translate 0 0 5\nCamera \"perspective\" \"float fov\" 30\nWorldBegin\n\
         CoordinateSystem \"here\"\nTranslate 1 0 0\nCoordinateSystem \"there\"\n\
         CoordSysTransform \"camera\"\nShape \"sphere\"\n\
         CoordSysTransform \"here\"\nShape \"sphere\"\nWorldEnd\n",
    );
    let cam = d.camera.as_ref().unwrap();
    assert_eq!(
        origin(cam.world_to_camera.start()),
        DVec3::new(0.0, 0.0, 5.0)
    );
    // A bare single value works for numbers.
    assert_eq!(cam.entity.params.float("fov"), Some(30.0));
    // Shapes under CoordSysTransform "camera" sit at the camera: camera-to-world.
    assert_eq!(
        origin(d.shapes[0].object_to_world.start()),
        DVec3::new(0.0, 0.0, -5.0)
    );
    assert_eq!(d.shapes[1].object_to_world.start(), DMat4::IDENTITY);
    assert_eq!(origin(d.coordinate_systems["there"]), DVec3::X);
    assert_eq!(d.coordinate_systems["world"], DMat4::IDENTITY);
}

#[test]
fn motion_blocks_give_keyed_transforms() {
    let d = parse(
        "WorldBegin\nTranslate 0 0 1\nMotionBegin [0 1]\nTranslate 0 0 0\nTranslate 2 0 0\nMotionEnd\n\
         Shape \"sphere\"\nWorldEnd\n",
    );
    let x = &d.shapes[0].object_to_world;
    assert!(x.is_animated());
    assert_eq!(x.keys.len(), 2);
    assert_eq!((x.keys[0].0, x.keys[1].0), (0.0, 1.0));
    assert_eq!(origin(x.keys[0].1), DVec3::new(0.0, 0.0, 1.0));
    assert_eq!(origin(x.keys[1].1), DVec3::new(2.0, 0.0, 1.0));
}

#[test]
fn objects_instances_and_their_lights() {
    let d = parse(
        "WorldBegin\nObjectBegin \"tree\"\n Translate 0 0 1\n Shape \"sphere\"\n\
         LightSource \"point\"\n Material \"matte\"\nObjectEnd\n\
         Shape \"disk\"\n\
         Translate 5 0 0\nObjectInstance \"tree\"\n\
         ObjectBegin \"forest\"\n ObjectInstance \"tree\"\nObjectEnd\nWorldEnd\n",
    );
    // ObjectEnd restored the CTM and the material (none).
    assert_eq!(d.shapes.len(), 1);
    assert_eq!(d.shapes[0].material, None);
    assert_eq!(d.objects.len(), 2);
    assert_eq!(
        origin(d.objects[0].shapes[0].object_to_world.start()),
        DVec3::Z
    );
    assert_eq!(d.instances.len(), 1);
    assert_eq!(d.instances[0].object, 0);
    assert_eq!(
        origin(d.instances[0].instance_to_world.start()),
        DVec3::new(5.0, 0.0, 0.0)
    );
    // The light inside the object is instanced with the instance transform.
    assert_eq!(d.lights.len(), 1);
    assert_eq!(
        origin(d.lights[0].light_to_world.start()),
        DVec3::new(5.0, 0.0, 1.0)
    );
    // An instance inside a definition is copied in, transformed.
    assert_eq!(d.objects[1].shapes.len(), 1);
    assert_eq!(
        origin(d.objects[1].shapes[0].object_to_world.start()),
        DVec3::new(5.0, 0.0, 1.0)
    );
}

#[test]
fn light_groups_area_lights_and_volumes() {
    let d = parse(
        "WorldBegin\nMakeNamedVolume \"water\" \"clear\" \"color absorption\" [1 1 1]\n\
         Exterior \"water\"\nLightSource \"infinite\"\n\
         AttributeBegin\nLightGroup \"lamps\"\nInterior \"water\"\n\
         AreaLightSource \"area\" \"color L\" [1 1 1]\nShape \"disk\"\nAttributeEnd\n\
         Shape \"sphere\"\nPortalShape \"disk\"\nWorldEnd\n",
    );
    assert_eq!(
        d.light_groups,
        vec!["default".to_string(), "lamps".to_string()]
    );
    assert_eq!(d.lights[0].light_group, "default");
    assert_eq!(d.lights[0].exterior.as_deref(), Some("water"));
    let lit = &d.shapes[0];
    assert_eq!(lit.area_light.as_ref().unwrap().light_group, "lamps");
    assert_eq!(lit.interior.as_deref(), Some("water"));
    assert!(d.shapes[1].area_light.is_none());
    assert!(d.shapes[1].interior.is_none());
    assert!(d.shapes[2].portal);
    assert_eq!(d.named_volumes["water"], 0);
    assert_eq!(d.camera, None);
}

#[test]
fn named_materials_take_kind_from_type_and_legacy_names_warn() {
    let d = parse(
        "Film \"multiimage\"\nSampler \"bestcandidate\"\nWorldBegin\n\
         MakeNamedMaterial \"p\" \"string type\" [\"plastic\"] \"color Kd\" [1 0 0]\n\
         Texture \"t\" \"float\" \"constant\" \"float value\" [0.5]\n\
         Material \"matte\" \"texture sigma\" \"t\"\n\
         LightSource \"sunsky\"\nWorldEnd\n",
    );
    let p = d.named_material("p").unwrap();
    assert_eq!(p.entity.kind, "plastic");
    assert!(p.entity.params.get("type").unwrap().is_used());
    assert_eq!(p.entity.params.unused().count(), 1);
    assert_eq!(d.film.as_ref().unwrap().kind, "multiimage");
    let msgs: Vec<String> = d.warnings.iter().map(|w| w.to_string()).collect();
    // "sunsky" is a current LuxRender 1.x plugin (sun + sky), not a legacy name.
    assert_eq!(msgs.len(), 3, "{msgs:?}");
    assert!(msgs[0].starts_with("t.lxs:1:1:") && msgs[0].contains("\"fleximage\""));
    assert!(msgs[1].contains("\"lowdiscrepancy\""));
    assert!(msgs[2].starts_with("t.lxs:4:1:") && msgs[2].contains("\"glossy\""));
    assert!(msgs.iter().all(|m| !m.contains("sunsky")));
    assert_eq!(
        d.texture(lxs::TextureType::Float, "t").unwrap().entity.kind,
        "constant"
    );
}

#[test]
fn strings_escapes_comments_and_typed_values() {
    let d = parse(
        "# header\nWorldBegin # trailing comment\n\
         Shape \"plymesh\" \"string filename\" \"a \\\"b\\\"\\tc.ply\" # x\n\
           \"bool smooth\" \"true\" \"integer n\" [1 -2 +3] \"spectrum s\" [400 0.5 500 0.7]\n\
           \"spectrum f\" \"file.spd\" \"vector v\" [0 0 1] \"normal N\" [0 1 0]\n\
           \"float a\" [1 # comment inside an array\n 2]\nWorldEnd\n",
    );
    let p = &d.shapes[0].entity.params;
    assert_eq!(p.string("filename"), Some("a \"b\"\tc.ply"));
    assert_eq!(p.bool("smooth"), Some(true));
    assert_eq!(p.ints("n"), Some(&[1, -2, 3][..]));
    assert_eq!(p.vector("v"), Some([0.0, 0.0, 1.0]));
    assert_eq!(p.normal("N"), Some([0.0, 1.0, 0.0]));
    assert_eq!(p.floats("a"), Some(&[1.0, 2.0][..]));
    assert!(matches!(p.spectrum("s"), Some(lxs::SpectrumValue::Numbers(v)) if v.len() == 4));
    assert!(matches!(p.spectrum("f"), Some(lxs::SpectrumValue::File(f)) if f == "file.spd"));
    assert_eq!(
        p.params[0].loc,
        Loc {
            file: "t.lxs".into(),
            line: 3,
            col: 17
        }
    );
}

/// A builder that only counts statements: the trait serves more than the description.
#[derive(Default)]
struct Counter {
    shapes: usize,
    statements: usize,
}

macro_rules! count {
    ($($name:ident($($arg:ident: $t:ty),*);)*) => {
        $(fn $name(&mut self, $($arg: $t),*) -> LxsResult<()> {
            $(let _ = $arg;)*
            self.statements += 1;
            Ok(())
        })*
    };
}

impl SceneBuilder for Counter {
    count! {
        identity(l: &Loc); translate(d: [f64; 3], l: &Loc); rotate(a: f64, x: [f64; 3], l: &Loc);
        scale(s: [f64; 3], l: &Loc); look_at(e: [f64; 3], t: [f64; 3], u: [f64; 3], l: &Loc);
        transform(m: [f64; 16], l: &Loc); concat_transform(m: [f64; 16], l: &Loc);
        coordinate_system(n: &str, l: &Loc); coord_sys_transform(n: &str, l: &Loc);
        motion_begin(t: Vec<f32>, l: &Loc); motion_end(l: &Loc); transform_begin(l: &Loc);
        transform_end(l: &Loc); camera(e: Entity); film(e: Entity); pixel_filter(e: Entity);
        sampler(e: Entity); surface_integrator(e: Entity); volume_integrator(e: Entity);
        accelerator(e: Entity); renderer(e: Entity); world_begin(l: &Loc); world_end(l: &Loc);
        attribute_begin(l: &Loc); attribute_end(l: &Loc); object_begin(n: &str, l: &Loc);
        object_end(l: &Loc); object_instance(n: &str, l: &Loc); portal_instance(n: &str, l: &Loc);
        motion_instance(n: &str, s: f32, e: f32, t: &str, l: &Loc);
        texture(n: &str, t: &str, e: Entity); material(e: Entity);
        make_named_material(n: &str, p: ParamSet, l: &Loc); named_material(n: &str, l: &Loc);
        light_group(n: &str, p: ParamSet, l: &Loc); light_source(e: Entity);
        area_light_source(e: Entity); portal_shape(e: Entity); reverse_orientation(l: &Loc);
        make_named_volume(n: &str, e: Entity); volume(e: Entity); interior(n: &str, l: &Loc);
        exterior(n: &str, l: &Loc); include(p: &str, l: &Loc); search_path(p: &str, l: &Loc);
        end_of_input(l: &Loc);
    }
    fn shape(&mut self, _e: Entity) -> LxsResult<()> {
        self.shapes += 1;
        self.statements += 1;
        Ok(())
    }
    fn warning(&mut self, _d: Diagnostic) {}
}

#[test]
fn another_builder_sees_every_statement() {
    let mut c = Counter::default();
    // No graphics-state rules here: the counter accepts a Shape before WorldBegin.
    let text = "Shape \"sphere\"\nWorldBegin\nShape \"disk\"\nAttributeEnd\n";
    lxs::parse_with(text.as_bytes(), "t.lxs", &ParseOptions::default(), &mut c).unwrap();
    assert_eq!((c.shapes, c.statements), (2, 5));
}

#[test]
fn texture_references_bind_like_luxrender_despite_shadowing() {
    let d = parse(
        "WorldBegin\n\
         Texture \"t\" \"color\" \"constant\" \"color value\" [1 0 0]\n\
         Material \"matte\" \"texture Kd\" \"t\"\n\
         AttributeBegin\n\
          Texture \"t\" \"color\" \"constant\" \"color value\" [0 1 0]\n\
          Material \"matte\" \"texture Kd\" \"t\"\n\
          AreaLightSource \"area\" \"texture L\" \"t\"\n\
          Shape \"disk\"\n\
         AttributeEnd\n\
         Material \"matte\" \"texture Kd\" \"t\"\n\
         WorldEnd\n",
    );
    let bound = |params: &lxs::ParamSet| {
        let name = params
            .texture("Kd")
            .or_else(|| params.texture("L"))
            .unwrap();
        d.named_textures[&(lxs::TextureType::Color, name.to_string())]
    };
    assert_eq!(
        d.named_textures[&(lxs::TextureType::Color, "t".to_string())],
        1
    );
    assert_eq!(bound(&d.materials[0].entity.params), 0);
    assert_eq!(bound(&d.materials[1].entity.params), 1);
    assert_eq!(bound(&d.materials[2].entity.params), 0);
    assert_eq!(
        bound(&d.shapes[0].area_light.as_ref().unwrap().entity.params),
        1
    );
    assert_eq!(d.materials[0].entity.params.texture("Kd"), Some("t@0"));
    assert!(d.warnings.iter().any(|w| w.message.contains("redefined")));
}

#[test]
fn mix_material_references_bind_in_scope() {
    let d = parse(
        "WorldBegin\n\
         MakeNamedMaterial \"a\" \"string type\" [\"matte\"]\n\
         MakeNamedMaterial \"b\" \"string type\" [\"glass\"]\n\
         MakeNamedMaterial \"m\" \"string type\" [\"mix\"] \"string namedmaterial1\" [\"a\"] \"string namedmaterial2\" [\"b\"]\n\
         MakeNamedMaterial \"a\" \"string type\" [\"metal\"]\n\
         WorldEnd\n",
    );
    let mix = d.named_material("m").unwrap();
    let first = mix.entity.params.string("namedmaterial1").unwrap();
    assert_eq!(first, "a@0");
    assert_eq!(d.named_material(first).unwrap().entity.kind, "matte");
    assert_eq!(mix.entity.params.string("namedmaterial2"), Some("b"));
    assert_eq!(d.named_material("a").unwrap().entity.kind, "metal");
}
