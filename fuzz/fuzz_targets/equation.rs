//! The equation compiler alone: any text, with a few `let` constants known.
//! What compiles is also asked for its bounds and evaluated at a point, so
//! the compiled forms are exercised as well as the parser and expander.
#![no_main]

use libfuzzer_sys::fuzz_target;
use raytrace::geometry::DVec3;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let constant = |n: &str| match n {
        "R" => Some(2.0),
        "r" => Some(0.5),
        "k" => Some(-3.0),
        "big" => Some(1e300),
        "zero" => Some(0.0),
        _ => None,
    };
    if let Ok(eq) = raytrace::implicit::Equation::compile(text, &constant) {
        assert!(eq.degree() <= raytrace::implicit::MAX_DEGREE);
        let p = DVec3::new(0.3, -0.7, 1.1);
        let _ = eq.value(p);
        let _ = eq.gradient(p);
        let _ = eq.on_written_branch(p);
        let _ = eq.auto_bounds();
    }
});
