//! Area sampling: uniformity and pdf normalisation.

use super::*;

fn mean_and_inverse_pdf(g: &Geometry, id: ShapeId, n: usize) -> (Vec3A, f64, Vec<Interaction>) {
    let mut rng = fixtures::Rng::new(5);
    let (mut sum, mut inv) = (Vec3A::ZERO, 0.0f64);
    let mut pts = Vec::new();
    for _ in 0..n {
        let (it, _, pdf) = g.sample(id, Vec2::new(rng.f32(), rng.f32()), rng.f32(), 0.0);
        assert!(pdf > 0.0 && pdf.is_finite());
        sum += it.p;
        inv += 1.0 / pdf as f64;
        pts.push(it);
    }
    (sum / n as f32, inv / n as f64, pts)
}

#[test]
fn area_sampling_is_uniform_and_pdf_integrates_to_one() {
    let hemi = sphere(
        vec![("radius", floats(&[2.0])), ("zmin", floats(&[0.0]))],
        false,
    );
    let g = geo(&[hemi]);
    assert!((g.area(ShapeId(0)) - 2.0 * PI * 4.0).abs() < 1e-3);
    let (mean, inv, pts) = mean_and_inverse_pdf(&g, ShapeId(0), 40_000);
    assert!(
        (mean.z - 1.0).abs() < 0.02,
        "Archimedes: centroid at r/2, got {}",
        mean.z
    );
    assert!((inv / g.area(ShapeId(0)) as f64 - 1.0).abs() < 1e-4);
    for it in &pts[..100] {
        assert!((it.p.length() - 2.0).abs() < 1e-5 && it.n.dot(it.p) > 0.0);
    }
    // every shape: E[1/pdf] equals the area (pdf integrates to 1 over the surface)
    let non_uniform = DMat4::from_scale(DVec3::new(2.0, 1.0, 0.5));
    let descs = [
        shape(
            "disk",
            vec![
                ("innerradius", floats(&[0.5])),
                ("phimax", floats(&[270.0])),
            ],
            DMat4::IDENTITY,
            false,
        ),
        shape(
            "cylinder",
            vec![],
            DMat4::from_scale(DVec3::splat(3.0)),
            false,
        ),
        shape(
            "cone",
            vec![("height", floats(&[2.0]))],
            DMat4::IDENTITY,
            false,
        ),
        shape(
            "paraboloid",
            vec![("zmin", floats(&[0.2]))],
            DMat4::IDENTITY,
            false,
        ),
        shape(
            "hyperboloid",
            vec![
                ("p1", points(&[[1.0, -1.0, -1.0]])),
                ("p2", points(&[[1.0, 1.0, 1.0]])),
            ],
            DMat4::IDENTITY,
            false,
        ),
        shape("sphere", vec![], non_uniform, false),
        quad(DMat4::from_scale(DVec3::new(1.0, 3.0, 1.0)), false),
    ];
    let g = geo(&descs);
    for (i, d) in descs.iter().enumerate() {
        let id = ShapeId(i as u32);
        let (_, inv, _) = mean_and_inverse_pdf(&g, id, 20_000);
        let a = g.area(id) as f64;
        assert!(
            (inv / a - 1.0).abs() < 0.02,
            "{}: E[1/pdf] {inv} vs area {a}",
            d.entity.kind
        );
    }
    // analytic areas
    let cone_area = PI * 1.0 * (1.0f32 + 4.0).sqrt();
    assert!((g.area(ShapeId(2)) - cone_area).abs() < 1e-4);
    let parab = PI / 6.0 * (5.0f32.powf(1.5) - 1.8f32.powf(1.5)); // z = r², r from sqrt(.2) to 1
    assert!(
        (g.area(ShapeId(3)) - parab).abs() < 1e-3,
        "{} vs {parab}",
        g.area(ShapeId(3))
    );
    assert!((g.area(ShapeId(6)) - 12.0).abs() < 1e-5);
    // paraboloid samples are uniform by area: mean z matches the area-weighted mean
    let (mean, _, _) = mean_and_inverse_pdf(&g, ShapeId(3), 40_000);
    let (mut num, mut den) = (0.0f64, 0.0f64);
    for k in 0..100_000 {
        let z = 0.2 + 0.8 * (k as f64 + 0.5) / 100_000.0;
        let w = (z + 0.25).sqrt(); // dA/dz ∝ sqrt(r² + r'²/4) with r² = z
        num += z * w;
        den += w;
    }
    assert!(
        (mean.z as f64 - num / den).abs() < 0.01,
        "{} vs {}",
        mean.z,
        num / den
    );
}

#[test]
fn only_shapes_prepared_for_sampling_are_sampled() {
    // Area-sampling tables are made for emitters only: an unprepared shape has its area but
    // no samples (pdf 0), and preparing it gives the same area.
    let mut b = GeometryBuilder::new();
    let q = quad(DMat4::from_scale(DVec3::new(1.0, 3.0, 1.0)), false);
    b.add_shape(&q, 0, &ShapeCtx::default())
        .expect("shape builds");
    let mut g = b.build();
    let area = g.area(ShapeId(0));
    assert!((area - 12.0).abs() < 1e-5);
    assert_eq!(g.sample(ShapeId(0), Vec2::splat(0.5), 0.5, 0.0).2, 0.0);
    assert_eq!(g.prepare_sampling(ShapeId(0)), area);
    let (_, _, pdf) = g.sample(ShapeId(0), Vec2::splat(0.5), 0.5, 0.0);
    assert!((pdf - 1.0 / 12.0).abs() < 1e-7);
    assert_eq!(g.prepare_sampling(ShapeId(7)), 0.0);
}

#[test]
fn sampled_mesh_points_carry_their_uv() {
    // uv equal to (x, y) at the vertices: a sampled point's uv must be its own (x, y), so a
    // textured area light is looked up where the point is (it was looked up at uv 0).
    let mut q = crate::shape::test_util::quad(DMat4::IDENTITY, false);
    q.entity.params.add(
        "uv",
        crate::shape::test_util::floats(&[-1.0, -1.0, 1.0, -1.0, 1.0, 1.0, -1.0, 1.0]),
    );
    let g = geo(&[q]);
    let mut rng = fixtures::Rng::new(3);
    for _ in 0..1000 {
        let (it, uv, pdf) = g.sample(ShapeId(0), Vec2::new(rng.f32(), rng.f32()), rng.f32(), 0.0);
        assert!(pdf > 0.0);
        assert!(
            (uv.x - it.p.x).abs() < 1e-5 && (uv.y - it.p.y).abs() < 1e-5,
            "{uv} at {}",
            it.p
        );
    }
}

#[test]
fn a_stratified_sample_stays_stratified_over_a_quads_two_triangles() {
    // A quad light is two triangles of equal area; its points come from the 2D sample alone
    // (the separate pick number is not used), so an 8 × 8 grid of samples puts exactly 32
    // points in each triangle, whatever `u_pick` says.
    let g = geo(&[crate::shape::test_util::quad(DMat4::IDENTITY, false)]);
    let mut rng = fixtures::Rng::new(11);
    let mut first = 0;
    for i in 0..64 {
        let u = Vec2::new((i % 8) as f32 + 0.5, (i / 8) as f32 + 0.5) / 8.0;
        let (it, _, pdf) = g.sample(ShapeId(0), u, rng.f32(), 0.0);
        assert!((pdf - 0.25).abs() < 1e-6, "the quad spans [-1, 1]²");
        let (again, _, _) = g.sample(ShapeId(0), u, rng.f32(), 0.0);
        assert_eq!(it.p, again.p, "u_pick chose the point");
        // The quad's first triangle is (-1,-1), (1,-1), (1,1): below the diagonal y = x.
        first += u32::from(it.p.y < it.p.x);
    }
    assert_eq!(first, 32);
}

/// `u_pick` is read exactly where `sample_reads_pick` says: not by a quad light or a
/// quadric (the same point for every `u_pick`), but by a mesh of more than 1024 triangles
/// (a different triangle for a different `u_pick`).
#[test]
fn u_pick_is_read_only_by_meshes_of_many_triangles() {
    let n = 48; // a 48 × 48 grid of quads: 4608 triangles
    let mut p = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            p.push([i as f32, j as f32, 0.0]);
        }
    }
    let mut idx = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            idx.extend([a, a + 1, a + n + 2, a, a + n + 2, a + n + 1]);
        }
    }
    let grid = shape(
        "trianglemesh",
        vec![("indices", ints(&idx)), ("P", points(&p))],
        DMat4::IDENTITY,
        false,
    );
    let g = geo(&[quad(DMat4::IDENTITY, false), sphere(vec![], false), grid]);
    let reads: Vec<bool> = (0..3).map(|i| g.sample_reads_pick(ShapeId(i))).collect();
    assert_eq!(reads, [false, false, true]);
    let mut rng = fixtures::Rng::new(9);
    let mut moved = 0;
    for _ in 0..200 {
        let (u, up) = (Vec2::new(rng.f32(), rng.f32()), rng.f32());
        for (i, &r) in reads.iter().enumerate() {
            let id = ShapeId(i as u32);
            let (a, b) = (g.sample(id, u, up, 0.0), g.sample(id, u, 1.0 - up, 0.0));
            if r {
                moved += usize::from(a.0.p != b.0.p);
            } else {
                assert_eq!(format!("{a:?}"), format!("{b:?}"), "shape {i} reads u_pick");
            }
        }
    }
    assert!(
        moved > 150,
        "the grid's point moved with u_pick in {moved} of 200 draws"
    );
}
