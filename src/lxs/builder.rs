//! The `SceneBuilder` trait: one method per .lxs statement, mirroring LuxRender's API.
//!
//! The parser reads text and calls these methods in file order (Includes are followed by the
//! parser and announced through [`SceneBuilder::include`]); a builder keeps whatever state it
//! needs. [`super::describe::DescriptionBuilder`] keeps LuxRender's graphics state and yields a
//! `SceneDescription`; other builders (a statement counter, a scene rewriter, ...) can be
//! written against the same trait. Every method may refuse a statement with an error that
//! names its location.

use super::description::{Diagnostic, Entity};
use super::error::LxsResult;
use super::params::{Loc, ParamSet};

/// Receives the statements of a scene, in order.
pub trait SceneBuilder {
    // -- transforms (allowed everywhere, also inside MotionBegin/MotionEnd) --
    fn identity(&mut self, loc: &Loc) -> LxsResult<()>;
    fn translate(&mut self, d: [f64; 3], loc: &Loc) -> LxsResult<()>;
    /// `Rotate angle x y z`: angle in degrees about the axis.
    fn rotate(&mut self, angle_deg: f64, axis: [f64; 3], loc: &Loc) -> LxsResult<()>;
    fn scale(&mut self, s: [f64; 3], loc: &Loc) -> LxsResult<()>;
    fn look_at(
        &mut self,
        eye: [f64; 3],
        target: [f64; 3],
        up: [f64; 3],
        loc: &Loc,
    ) -> LxsResult<()>;
    /// `Transform [16 numbers]`, given column by column.
    fn transform(&mut self, m: [f64; 16], loc: &Loc) -> LxsResult<()>;
    /// `ConcatTransform [16 numbers]`, given column by column.
    fn concat_transform(&mut self, m: [f64; 16], loc: &Loc) -> LxsResult<()>;
    fn coordinate_system(&mut self, name: &str, loc: &Loc) -> LxsResult<()>;
    fn coord_sys_transform(&mut self, name: &str, loc: &Loc) -> LxsResult<()>;
    fn motion_begin(&mut self, times: Vec<f32>, loc: &Loc) -> LxsResult<()>;
    fn motion_end(&mut self, loc: &Loc) -> LxsResult<()>;
    fn transform_begin(&mut self, loc: &Loc) -> LxsResult<()>;
    fn transform_end(&mut self, loc: &Loc) -> LxsResult<()>;

    // -- options block --
    fn camera(&mut self, e: Entity) -> LxsResult<()>;
    fn film(&mut self, e: Entity) -> LxsResult<()>;
    fn pixel_filter(&mut self, e: Entity) -> LxsResult<()>;
    fn sampler(&mut self, e: Entity) -> LxsResult<()>;
    fn surface_integrator(&mut self, e: Entity) -> LxsResult<()>;
    fn volume_integrator(&mut self, e: Entity) -> LxsResult<()>;
    fn accelerator(&mut self, e: Entity) -> LxsResult<()>;
    fn renderer(&mut self, e: Entity) -> LxsResult<()>;
    fn world_begin(&mut self, loc: &Loc) -> LxsResult<()>;

    // -- world block --
    fn world_end(&mut self, loc: &Loc) -> LxsResult<()>;
    fn attribute_begin(&mut self, loc: &Loc) -> LxsResult<()>;
    fn attribute_end(&mut self, loc: &Loc) -> LxsResult<()>;
    fn object_begin(&mut self, name: &str, loc: &Loc) -> LxsResult<()>;
    fn object_end(&mut self, loc: &Loc) -> LxsResult<()>;
    fn object_instance(&mut self, name: &str, loc: &Loc) -> LxsResult<()>;
    fn portal_instance(&mut self, name: &str, loc: &Loc) -> LxsResult<()>;
    /// Deprecated `MotionInstance "name" start end "tocoordsys"`.
    fn motion_instance(
        &mut self,
        name: &str,
        start: f32,
        end: f32,
        to: &str,
        loc: &Loc,
    ) -> LxsResult<()>;
    /// `Texture "name" "float|color" "class" params`.
    fn texture(&mut self, name: &str, value_type: &str, e: Entity) -> LxsResult<()>;
    fn material(&mut self, e: Entity) -> LxsResult<()>;
    /// `MakeNamedMaterial "name" params` (the kind is the `type` parameter).
    fn make_named_material(&mut self, name: &str, params: ParamSet, loc: &Loc) -> LxsResult<()>;
    fn named_material(&mut self, name: &str, loc: &Loc) -> LxsResult<()>;
    fn light_group(&mut self, name: &str, params: ParamSet, loc: &Loc) -> LxsResult<()>;
    fn light_source(&mut self, e: Entity) -> LxsResult<()>;
    fn area_light_source(&mut self, e: Entity) -> LxsResult<()>;
    fn shape(&mut self, e: Entity) -> LxsResult<()>;
    fn portal_shape(&mut self, e: Entity) -> LxsResult<()>;
    fn reverse_orientation(&mut self, loc: &Loc) -> LxsResult<()>;
    fn make_named_volume(&mut self, name: &str, e: Entity) -> LxsResult<()>;
    fn volume(&mut self, e: Entity) -> LxsResult<()>;
    fn interior(&mut self, name: &str, loc: &Loc) -> LxsResult<()>;
    fn exterior(&mut self, name: &str, loc: &Loc) -> LxsResult<()>;

    // -- file level --
    /// `Include "file"`: called with the resolved path before the parser reads it.
    fn include(&mut self, path: &str, loc: &Loc) -> LxsResult<()>;
    /// `SearchPath "dir"` (accepted by LuxRender's grammar, never implemented there).
    fn search_path(&mut self, path: &str, loc: &Loc) -> LxsResult<()>;
    /// A problem the parser noticed that does not stop parsing.
    fn warning(&mut self, d: Diagnostic);
    /// The end of the root file: a builder checks for unclosed blocks here.
    fn end_of_input(&mut self, loc: &Loc) -> LxsResult<()>;
}
