//! CSG end to end, written in the scene language: every kind of solid in
//! `difference`/`union`/`intersection` (implicit surfaces, closed meshes,
//! tori, cones, nested results), checked against a second way of building
//! the same solid, on crossing lists and on rendered pictures.

use crate::support::{
    build_src, max_difference, pixels_differing, project_root, render_path, scene_file,
};
use raytrace::geometry::{DVec3, Ray};
use raytrace::render::Film;
use raytrace::shapes::{Hit, Shape};

/// Builds a scene from text and returns its objects.
fn objects(src: &str) -> Vec<Box<dyn Shape>> {
    build_src(src).objects
}

fn render(src: &str) -> Film {
    let (_dir, path) = scene_file(src);
    render_path(&path, None, 2)
}

/// Rays from a sphere of radius 10 around `target`, aimed within `spread` of it.
fn rays(target: DVec3, spread: f64, n: usize, mut seed: u64) -> Vec<Ray> {
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    (0..n)
        .map(|_| {
            let o = target + DVec3::new(rnd(), rnd(), rnd()).normalize_or(DVec3::X) * 10.0;
            let aim = target + DVec3::new(rnd(), rnd(), rnd()) * spread;
            Ray::new(o, (aim - o).normalize())
        })
        .collect()
}

fn crossings(s: &dyn Shape, r: &Ray) -> Vec<Hit> {
    let mut v = Vec::new();
    s.crossings(r, &mut v);
    v
}

/// Crossings that alternate entering and leaving, starting outside.
fn assert_alternating(list: &[Hit], r: &Ray) {
    assert!(list.len().is_multiple_of(2), "odd crossings {list:?}");
    for (i, h) in list.iter().enumerate() {
        assert_eq!(
            h.normal.dot(r.dir) < 0.0,
            i % 2 == 0,
            "crossing {i} of {list:?}"
        );
    }
}

/// Whether two crossing lists agree: same count, t within `tol`, same
/// material and the same way through (entering or leaving).
fn agree(a: &[Hit], b: &[Hit], r: &Ray, tol: f64) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            (x.t - y.t).abs() < tol
                && x.material == y.material
                && (x.normal.dot(r.dir) < 0.0) == (y.normal.dot(r.dir) < 0.0)
        })
}

const HEAD: &str = r#"
camera { position <0, 3, 9>  look_at <0, 0, 0>  fov 50 }
render { width 80  height 60 }
ambient rgb(1, 1, 1) intensity 0.1
light { position <0, 3, 9> }
material a { colour rgb(0.9, 0.3, 0.2) }
material b { colour rgb(0.2, 0.4, 0.9) }
"#;

/// The course's torus (ring of radius 3 in the x-y plane, tube 0.5) minus
/// a box that bites off a piece, turned so the cut faces show.
fn torus_minus_box(torus: &str) -> String {
    format!(
        "{HEAD}
difference {{
  {torus}
  box {{ min <0.5, -0.5, -1>  max <4, 4, 1>  material b }}
  rotate y -25  rotate x 20
}}"
    )
}

const COURSE_TORUS: &str = r#"implicit "(((x^2 + y^2)_2 - 3)^2 + z^2)_2 - 0.5" { material a }"#;
const PRIMITIVE_TORUS: &str = "torus { major 3  minor 0.5  material a  rotate x 90 }";

#[test]
fn implicit_torus_minus_box_agrees_with_torus_primitive_minus_box() {
    let _watchdog = crate::watchdog::start();
    let implicit = objects(&torus_minus_box(COURSE_TORUS));
    let primitive = objects(&torus_minus_box(PRIMITIVE_TORUS));
    let (i, p) = (&*implicit[0], &*primitive[0]);
    let mut per_material = std::collections::BTreeMap::new();
    for r in rays(DVec3::ZERO, 3.5, 3000, 0x5eed) {
        let (a, b) = (crossings(i, &r), crossings(p, &r));
        assert!(agree(&a, &b, &r, 1e-7), "{a:?}\nvs\n{b:?}\nfor {r:?}");
        assert_alternating(&a, &r);
        for h in &a {
            *per_material.entry(h.material).or_insert(0) += 1;
        }
        let (x, y) = (
            i.intersect(&r, 1e-9, f64::INFINITY),
            p.intersect(&r, 1e-9, f64::INFINITY),
        );
        assert_eq!(x.map(|h| h.material), y.map(|h| h.material));
    }
    // Both the torus's own surface and the box's cut faces were crossed.
    let counts: Vec<i32> = per_material.values().copied().collect();
    assert!(
        counts.len() == 2 && counts.iter().all(|&n| n > 50),
        "{per_material:?}"
    );
    // The pictures agree too (both materials in view).
    let (fi, fp) = (
        render(&torus_minus_box(COURSE_TORUS)),
        render(&torus_minus_box(PRIMITIVE_TORUS)),
    );
    assert!(
        max_difference(&fi, &fp) < 1e-4,
        "{}",
        max_difference(&fi, &fp)
    );
    assert!(fi.pixels.iter().any(|p| p[0] > 0.3 && p[2] < 0.2));
    assert!(fi.pixels.iter().any(|p| p[2] > 0.3 && p[0] < 0.2));
}

fn ball_minus_box(ball: &str) -> String {
    format!(
        "{HEAD}
difference {{
  {ball}
  box {{ min <0, 0, 0>  max <2, 2, 2>  material b }}
  rotate y -40
}}"
    )
}

#[test]
fn closed_mesh_sphere_minus_box_agrees_with_sphere_minus_box() {
    let _watchdog = crate::watchdog::start();
    let ply = project_root().join("examples/meshes/icosphere.ply");
    let mesh = format!(r#"mesh "{}" {{ smooth  material a }}"#, ply.display());
    let m = objects(&ball_minus_box(&mesh));
    let s = objects(&ball_minus_box("sphere { radius 1  material a }"));
    let (mut same, mut total) = (0, 0);
    for r in rays(DVec3::ZERO, 1.2, 2000, 0xba11) {
        let (a, b) = (crossings(&*m[0], &r), crossings(&*s[0], &r));
        assert_alternating(&a, &r);
        total += 1;
        // 1280 triangles: the surface is within 0.01 of the sphere; only
        // rays grazing it or the bite's rim may see a different story.
        if agree(&a, &b, &r, 0.03) {
            same += 1;
        }
    }
    assert!(same * 100 >= total * 97, "{same} of {total} agree");
    let (fm, fs) = (
        render(&ball_minus_box(&mesh)),
        render(&ball_minus_box("sphere { radius 1  material a }")),
    );
    let differ = fm
        .pixels
        .iter()
        .zip(&fs.pixels)
        .filter(|(p, q)| (0..3).any(|k| (p[k] - q[k]).abs() > 0.1))
        .count();
    assert!(differ * 100 < fm.pixels.len() * 2, "{differ} pixels differ");
    assert!(
        fm.pixels.iter().any(|p| p[2] > 0.3 && p[0] < 0.2),
        "the cut shows"
    );
}

/// Each solid, united with itself and intersected with itself, is itself;
/// and its crossings alternate. Every kind of solid the language has.
#[test]
fn every_solid_is_its_own_union_and_intersection() {
    let _watchdog = crate::watchdog::start();
    let ply = project_root().join("examples/meshes/icosphere.ply");
    let solids = [
        "sphere { radius 1  material a }".to_string(),
        "box { min <-1, -0.5, -0.8>  max <1, 0.7, 0.9>  material a }".to_string(),
        "cylinder { radius 0.8  height 2  material a  rotate x 30 }".to_string(),
        "cone { radius 1  height 2  material a  rotate z 20 }".to_string(),
        "cone { radius 1  top_radius 0.4  height 1.5  material a }".to_string(),
        "torus { major 1  minor 0.35  material a  rotate x 60 }".to_string(),
        COURSE_TORUS.replace("material a", "material a  scale 0.3"),
        r#"implicit "x^4 + y^4 + z^4 - 1" { material a }"#.to_string(),
        format!(
            r#"mesh "{}" {{ flat  material a  scale <1, 0.6, 1> }}"#,
            ply.display()
        ),
        "difference { sphere { radius 1 } box { min <0, 0, 0> max <2, 2, 2> } material a }"
            .to_string(),
    ];
    for solid in &solids {
        let alone = objects(&format!("{HEAD}{solid}"));
        let u = objects(&format!("{HEAD}union {{ {solid} {solid} }}"));
        let i = objects(&format!("{HEAD}intersection {{ {solid} {solid} }}"));
        let mut seen = 0;
        for r in rays(DVec3::ZERO, 1.2, 400, 0xab) {
            let want = crossings(&*alone[0], &r);
            assert_alternating(&want, &r);
            for other in [&u, &i] {
                let got = crossings(&*other[0], &r);
                assert!(
                    agree(&got, &want, &r, 1e-9),
                    "{solid}: {got:?}\nvs\n{want:?}"
                );
            }
            seen += want.len();
        }
        assert!(seen > 100, "{solid}: only {seen} crossings");
    }
}

/// Points along a ray are inside the result exactly when the analytic
/// predicate says so: (cone ∪ implicit ball) minus torus.
#[test]
fn mixed_solids_match_the_analytic_shape() {
    let _watchdog = crate::watchdog::start();
    let src = format!(
        r#"{HEAD}
difference {{
  union {{
    cone {{ radius 1  height 2  material a }}
    implicit "x^2 + y^2 + z^2 - 0.64" {{ material a  translate <0.8, 0, 0> }}
  }}
  torus {{ major 0.9  minor 0.3  material b }}
}}"#
    );
    let s = objects(&src);
    let in_cone = |p: DVec3| {
        // Base radius 1 at y = -1, apex at y = 1.
        p.y > -1.0 && p.y < 1.0 && (p.x * p.x + p.z * p.z).sqrt() < (1.0 - p.y) / 2.0
    };
    let in_ball = |p: DVec3| (p - DVec3::new(0.8, 0.0, 0.0)).length() < 0.8;
    let in_torus = |p: DVec3| {
        let rho = (p.x * p.x + p.z * p.z).sqrt();
        ((rho - 0.9).powi(2) + p.y * p.y).sqrt() < 0.3
    };
    let inside = |p: DVec3| (in_cone(p) || in_ball(p)) && !in_torus(p);
    let mut checked = 0;
    for r in rays(DVec3::new(0.3, 0.0, 0.0), 1.2, 600, 0xc0e) {
        let list = crossings(&*s[0], &r);
        assert_alternating(&list, &r);
        for k in 0..240 {
            let t = 7.0 + k as f64 * 0.025 + 0.00123;
            if list.iter().any(|h| (h.t - t).abs() < 1e-6) {
                continue;
            }
            let by_list = list
                .iter()
                .rev()
                .find(|h| h.t < t)
                .is_some_and(|h| h.normal.dot(r.dir) < 0.0);
            assert_eq!(by_list, inside(r.at(t)), "at {:?}", r.at(t));
            checked += by_list as usize;
        }
    }
    assert!(checked > 1000, "{checked} inside samples");
}

/// The course's view from inside a union of two spheres (camera and light
/// inside): the union shows only the far wall, a group also the inner one.
#[test]
fn from_inside_a_union_and_a_group_of_two_spheres() {
    let _watchdog = crate::watchdog::start();
    let scene = |op: &str| {
        format!(
            "camera {{ position <0, 0, 0>  look_at <1, 0, 0>  fov 60 }}
render {{ width 30  height 20 }}
ambient rgb(1, 1, 1) intensity 0.1
light {{ position <0, 0, 0> }}
{op} {{
  sphere {{ centre <-0.5, 0, 0>  radius 1  material {{ colour rgb(1, 0, 0) }} }}
  sphere {{ centre <0.5, 0, 0>  radius 1  material {{ colour rgb(0, 1, 0) }} }}
}}"
        )
    };
    let union = render(&scene("union"));
    assert!(
        union.pixels.iter().all(|p| p[0] == 0.0 && p[1] > 0.5),
        "only green, lit"
    );
    let group = render(&scene("group"));
    let centre = group.get(15, 10);
    assert!(centre[0] > 0.5 && centre[1] == 0.0, "{centre:?}");
}

/// An implicit whose `bounded_by` box cuts it is the solid "equation < 0
/// inside the box": in CSG the box faces where it is cut are surfaces, so
/// the implicit cylinder, cone and frustum cut by their boxes are the
/// capped primitives. Before, a ray entering the box where the equation is
/// negative got no entering crossing and the caps (and the fronts behind
/// them) were lost.
#[test]
fn bounded_implicit_cut_by_its_box_equals_its_primitive_twin() {
    let _watchdog = crate::watchdog::start();
    let twins = [
        (
            // Radius 1, y from −1 to 1.
            r#"implicit "x^2 + z^2 - 1" { bounded_by <-2, -1, -2> <2, 1, 2>  material a }"#,
            "cylinder { radius 1  height 2  material a }",
        ),
        (
            // Base radius 1 at y = −1, apex at y = 1: radius (1 − y)/2.
            r#"implicit "x^2 + z^2 - ((1 - y)/2)^2" { bounded_by <-2, -1, -2> <2, 1, 2>  material a }"#,
            "cone { radius 1  height 2  material a }",
        ),
        (
            // Radius 1 at y = −1 to 0.5 at y = 1: radius (3 − y)/4.
            r#"implicit "x^2 + z^2 - ((3 - y)/4)^2" { bounded_by <-2, -1, -2> <2, 1, 2>  material a }"#,
            "cone { radius 1  top_radius 0.5  height 2  material a }",
        ),
    ];
    for (implicit, primitive) in twins {
        // Inside a union with nothing else, tilted so the caps face the
        // camera; the primitive the same way.
        let wrap = |s: &str| format!("{HEAD}\nunion {{ {s}  rotate x 35  rotate z 20 }}");
        let (i, p) = (objects(&wrap(implicit)), objects(&wrap(primitive)));
        let (mut caps, mut checked) = (0, 0);
        for r in rays(DVec3::ZERO, 1.3, 2000, 0xca95) {
            let (a, b) = (crossings(&*i[0], &r), crossings(&*p[0], &r));
            assert!(
                agree(&a, &b, &r, 1e-7),
                "{implicit}\n{a:?}\nvs\n{b:?}\nfor {r:?}"
            );
            assert_alternating(&a, &r);
            checked += a.len();
            // Points on a cap: |y| = 1 in the solid's own frame, found as
            // crossings whose normal is the tilted ±y axis.
            use raytrace::geometry::Transform;
            let tilt = Transform::rotate(DVec3::X, 35.0)
                .and_then(|x| Some(x.then(&Transform::rotate(DVec3::Z, 20.0)?)))
                .expect("rotations");
            let y = tilt.vector(DVec3::Y);
            caps += a
                .iter()
                .filter(|h| h.normal.normalize().dot(y).abs() > 1.0 - 1e-9)
                .count();
        }
        assert!(
            caps > 100 && checked > 1000,
            "{implicit}: {caps} caps of {checked}"
        );
        // And the pictures agree.
        let (fi, fp) = (render(&wrap(implicit)), render(&wrap(primitive)));
        let differ = pixels_differing(&fi, &fp, 1e-3);
        assert_eq!(differ, 0, "{implicit}: {differ} pixels differ");
    }
}
