//! The `many` work (100,000 objects from a loop): the evaluator's
//! shortcuts must change no scene. A block that binds nothing shares its
//! parent's scope instead of making one, and a loop's variable name is
//! shared by all its iterations; these tests hold by construction: a block
//! that does bind keeps its names to itself, and a loop-built scene equals
//! the same scene written out.

use super::lang::{Files, try_build};
use raytrace::geometry::Aabb;
use raytrace::scene::Scene;

const STAGE: &str = "camera { position <0, 4, 12>  look_at <0, 1, 0> }\n\
    render { width 48  height 36 }\n\
    light { position <5, 10, 5> }\n";

fn build(src: &str) -> Scene {
    let f = Files::new();
    let p = f.write("scene.rt", &format!("{STAGE}{src}"));
    try_build(&p).unwrap_or_else(|e| panic!("scene did not build: {e:#?}"))
}

fn boxes(s: &Scene) -> Vec<Aabb> {
    s.objects.iter().map(|o| o.bounds()).collect()
}

#[test]
fn sibling_blocks_that_bind_one_name_each_keep_their_own() {
    // Were a binding block given its parent's scope, the second `let r`
    // would be "already defined" and the radii would not be 1 and 2.
    let s = build(
        "group { let r = 1  sphere { radius r } }\n\
         group { let r = 2  sphere { centre <5, 0, 0> radius r } }\n",
    );
    let b = boxes(&s);
    assert_eq!(b.len(), 2);
    let widths: Vec<f64> = b.iter().map(|b| b.max.x - b.min.x).collect();
    assert!((widths[0] - 2.0).abs() < 1e-9, "{widths:?}");
    assert!((widths[1] - 4.0).abs() < 1e-9, "{widths:?}");
}

#[test]
fn a_block_that_binds_nothing_still_sees_the_loop_variable() {
    // Each sphere's block and its material's block bind nothing: they read
    // `i` from the iteration's scope. Same boxes as written out.
    let looped = build(
        "for i in 0..3 { sphere { centre <i, 0, 0> radius 0.1 + i / 10 \
         material { colour rgb(i / 3, 0, 0) } } }\n",
    );
    let written = build(
        "sphere { centre <0, 0, 0> radius 0.1  material { colour rgb(0, 0, 0) } }\n\
         sphere { centre <1, 0, 0> radius 0.2  material { colour rgb(1 / 3, 0, 0) } }\n\
         sphere { centre <2, 0, 0> radius 0.3  material { colour rgb(2 / 3, 0, 0) } }\n",
    );
    let (a, b) = (boxes(&looped), boxes(&written));
    assert_eq!(a.len(), 3);
    for (x, y) in a.iter().zip(&b) {
        assert!((x.min - y.min).abs().max_element() < 1e-12, "{x:?} {y:?}");
        assert!((x.max - y.max).abs().max_element() < 1e-12, "{x:?} {y:?}");
    }
}

#[test]
fn a_let_inside_a_loop_body_block_is_fresh_each_iteration() {
    // Each iteration's scope is new, so binding `r` again in the next
    // iteration's group is no "already defined" (the loop's own scope,
    // kept whatever the group's block does).
    let s =
        build("for i in 1..=2 { group { let r = i  sphere { centre <3 * i, 0, 0> radius r } } }\n");
    let widths: Vec<f64> = boxes(&s).iter().map(|b| b.max.x - b.min.x).collect();
    assert_eq!(widths.len(), 2);
    assert!(
        (widths[0] - 2.0).abs() < 1e-9 && (widths[1] - 4.0).abs() < 1e-9,
        "{widths:?}"
    );
}
