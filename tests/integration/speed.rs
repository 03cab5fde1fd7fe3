//! What `--stats` reports of the work done (rays by kind, shaft culling,
//! acceleration memory), checked against counts a scene fixes.

use crate::support::*;

/// The numbers after `label ` in the stats text, e.g. "refracted 12".
fn count(stats: &str, label: &str) -> u64 {
    let key = format!("{label} ");
    let at = stats
        .find(&key)
        .unwrap_or_else(|| panic!("no {label:?} in {stats}"));
    let digits: String = stats[at + key.len()..]
        .chars()
        .take_while(|c| c.is_ascii_digit())
        .collect();
    digits.parse().unwrap()
}

fn stats_of(src: &str) -> String {
    let (dir, scene) = scene_file(src);
    let o = render_to(&scene, &dir.path().join("out.png"), &["--stats"]);
    assert!(o.status.success(), "{}", stderr(&o));
    stderr(&o)
}

#[test]
fn stats_count_reflected_and_refracted_rays_apart() {
    let _watchdog = crate::watchdog::start();
    // A glass ball filling the middle of the picture, nothing else: each
    // camera ray that meets it casts one reflected ray and, entering
    // (never totally reflected), one refracted ray; rays inside go on.
    let glass = "
camera { position <0, 0, 4>  look_at <0, 0, 0>  fov 40 }
render { width 20  height 20  max_depth 1 }
light { position <1, 2, 3> }
sphere { radius 1  material { refract { ior 1.5 } } }
";
    let s = stats_of(glass);
    let (primary, reflected, refracted) = (
        count(&s, "primary"),
        count(&s, "reflected"),
        count(&s, "refracted"),
    );
    assert_eq!(primary, 400);
    // max_depth 1: only the primary hits spawn, one of each per hit.
    assert!(refracted > 100, "{s}");
    assert_eq!(reflected, refracted, "{s}");
    let shadow = count(&s, "shadow");
    let total: u64 = s
        .lines()
        .find(|l| l.starts_with("rays "))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|n| n.parse().ok())
        .unwrap();
    assert_eq!(total, primary + reflected + refracted + shadow, "{s}");
    // The same ball as a mirror: reflected rays, none refracted.
    let s = stats_of(&glass.replace("refract { ior 1.5 }", "reflect 1"));
    assert_eq!(count(&s, "refracted"), 0, "{s}");
    assert_eq!(count(&s, "reflected"), refracted, "{s}");
    assert!(s.contains("rays/s") && s.contains("shadow "), "{s}");
}

#[test]
fn pixels_of_many_samples_find_their_first_hits_through_a_beam() {
    let _watchdog = crate::watchdog::start();
    // A few objects over a floor: with 3 x 3 samples, and through a lens,
    // every camera ray is looked for among its pixel's beam's objects;
    // with one sample a pixel none is (a beam would cost more than it
    // saves).
    let scene = |lens: &str, samples: &str| {
        format!(
            "
camera {{ position <0, 2, 6>  look_at <0, 0.5, 0>  fov 40 {lens} }}
render {{ width 12  height 10 {samples} }}
light {{ position <3, 5, 4> }}
sphere {{ centre <-1, 0.5, 0>  radius 0.5 }}
sphere {{ centre <1, 0.5, 0>  radius 0.5 }}
box {{ min <-0.3, 0, 1>  max <0.3, 0.6, 1.6> }}
plane {{ normal <0, 1, 0> }}
"
        )
    };
    for (lens, samples, primary, beamed) in [
        ("", "", 120, 0),
        ("", "samples 3", 1080, 1080),
        ("aperture 0.1  focus 6", "samples <4, 2>", 960, 960),
        ("aperture 0.1  focus 6", "", 120, 0),
    ] {
        let s = stats_of(&scene(lens, samples));
        assert_eq!(count(&s, "primary"), primary, "{lens} {samples}: {s}");
        assert_eq!(count(&s, "beamed"), beamed, "{lens} {samples}: {s}");
    }
}

/// A 2 × 2 light with its own 4 × 4 grid over a floor seen from below it,
/// and `extra` objects.
fn grid_light_scene(extra: &str) -> String {
    format!(
        "
camera {{ position <0, 4, 0.01>  look_at <0, 0, 0>  fov 60 }}
render {{ width 16  height 16 }}
material lamp {{ emit white  intensity 4 }}
rectangle {{ bottom_left <-1, 5, -1>  top_left <-1, 5, 1>  bottom_right <1, 5, -1>  material lamp  samples 4 }}
plane {{ normal <0, 1, 0> }}
{extra}
"
    )
}

#[test]
fn an_open_floor_settles_every_shadow_ray_and_a_blocker_only_some() {
    let _watchdog = crate::watchdog::start();
    // The camera, under the light, sees only the floor: 16 shadow rays per
    // pixel, none of which can meet anything.
    let s = stats_of(&grid_light_scene(""));
    let shadow = count(&s, "shadow");
    assert_eq!(shadow, 16 * 256, "{s}");
    assert!(
        s.contains(&format!("shadow {shadow}: {shadow} settled")),
        "{s}"
    );
    // A ball on the floor under the light: the floor around it is in its
    // shaft, so those rays are cast, the far floor's are not.
    let s = stats_of(&grid_light_scene(
        "sphere { centre <0, 0.5, 0>  radius 0.5 }",
    ));
    let shadow = count(&s, "shadow");
    let settled: u64 = s
        .split(&format!("shadow {shadow}: "))
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{s}"));
    assert!(
        settled > 0 && settled < shadow,
        "{settled} of {shadow}: {s}"
    );
}

#[test]
fn with_glass_in_the_scene_clear_grid_rays_are_settled_and_light_the_same() {
    let _watchdog = crate::watchdog::start();
    // A glass ball far off to the side, in no shaft and out of view: the
    // scene now has glass, so its shadow rays take the route that can go
    // through glass, which must settle the clear ones as the opaque route
    // does and light the floor the same, pixel for pixel.
    let far_glass = "sphere { centre <30, 1, 0>  radius 0.5  material { refract { ior 1.5 } } }";
    let (plain, ps) = render_stats(&grid_light_scene(""), None, 1);
    let (glassy, gs) = render_stats(&grid_light_scene(far_glass), None, 1);
    for s in [&ps, &gs] {
        assert_eq!((s.rays.shadow, s.rays.settled), (16 * 256, 16 * 256));
    }
    assert_eq!(max_difference(&plain, &glassy), 0.0);
    assert!(luminance(glassy.get(8, 8)) > 0.1, "{:?}", glassy.get(8, 8));
}

#[test]
fn the_memory_line_counts_the_mesh_trees() {
    let _watchdog = crate::watchdog::start();
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("tet.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    )
    .unwrap();
    let scene = dir.path().join("scene.rt");
    std::fs::write(
        &scene,
        "camera { position <0, 0, 4>  look_at <0, 0, 0> }\nrender { width 8  height 8 }\n\
         light { position <1, 2, 3> }\nmesh \"tet.obj\" { }\nsphere { centre <3, 0, 0> }\n",
    )
    .unwrap();
    // Each structure counts its own bytes: the kd-trees' nodes (8 B) and
    // item references (4 B), or the BVHs' wide nodes; the other's are 0.
    for (accel, counted, unused) in [
        (
            "kdtree",
            ["scene tree", "mesh trees"],
            ["scene BVH", "mesh BVHs"],
        ),
        (
            "bvh",
            ["scene BVH", "mesh BVHs"],
            ["scene tree", "mesh trees"],
        ),
    ] {
        let o = render_to(
            &scene,
            &dir.path().join("out.png"),
            &["--stats", "--accel", accel],
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let s = stderr(&o);
        let line = s
            .lines()
            .find(|l| l.trim_start().starts_with("memory"))
            .unwrap();
        for name in counted {
            assert!(!line.contains(&format!("{name} 0 B")), "{accel}: {line}");
        }
        for name in unused {
            assert!(line.contains(&format!("{name} 0 B")), "{accel}: {line}");
        }
    }
}
