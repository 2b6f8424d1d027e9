//! Every .igmesh sample of ../shared loads with the counts it holds.

mod render_util;

use luxfarm::formats::indigo::igmesh::{read, Limits};

const LIMITS: Limits = Limits {
    max_array_len: 1 << 28,
    max_decompressed: 1 << 30,
};

#[test]
fn print_counts() {
    let dir = render_util::shared_dir().join("scenes/formats/indigo/igmesh");
    for f in ["bug-2", "tilted_prism", "cuboid", "cornell_box", "single_quad", "teapot"] {
        let bytes = std::fs::read(dir.join(format!("{f}.igmesh"))).unwrap();
        let m = read(&bytes, LIMITS).unwrap();
        println!(
            "{f}: v {} n {} uvsets {} uvs {} tris {} quads {} mats {:?} layout {:?} sets {:?}",
            m.positions.len(),
            m.normals.len(),
            m.num_uv_sets,
            m.uvs.len(),
            m.tris.len(),
            m.quads.len(),
            m.material_names,
            m.uv_layout,
            m.uv_set_names
        );
    }
}
