//! The benchmark scenes with implicit surfaces (benchmarks.md), built in
//! code: the renderer's tests and benches use them without the `.rt`
//! parser. `benches/scenes/*.rt` hold the same scenes in the language.

use super::{Equation, ImplicitSurface};
use crate::geometry::{Aabb, DVec3, Transform};
use crate::scene::{
    Camera, Colour, Light, Material, Projection, RenderSettings, Scene, Texture, Transfer,
};
use crate::shapes::{Plane, Shape, Torus, Transformed};

/// How the benchmark torus is made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TorusKind {
    /// `(x^2+y^2+z^2+R^2-r^2)^2 - 4R^2(x^2+y^2)` with `bounded_by`.
    Implicit,
    /// The same without `bounded_by` (the automatic box).
    ImplicitAutoBound,
    /// The `torus` primitive.
    Native,
}

fn base(position: DVec3, look_at: DVec3, fov: f64, light: DVec3, size: u32) -> Scene {
    Scene {
        camera: Camera {
            position,
            look_at,
            up: DVec3::Y,
            projection: Projection::Fov(fov),
            lens: None,
        },
        settings: RenderSettings {
            width: size,
            height: size,
            max_depth: 4,
            background: Colour::new(0.05, 0.05, 0.1),
            transfer: Transfer::Linear,
            samples: 1,
            ..RenderSettings::default()
        },
        ambient: Colour::splat(0.1),
        lights: vec![Light::point(light, Colour::ONE)],
        materials: vec![Material::default()],
        ..Scene::default()
    }
}

fn material(scene: &mut Scene, c: Colour, reflect: f64) -> u32 {
    scene
        .materials
        .push(Material::matte(Texture::Solid(c), reflect));
    (scene.materials.len() - 1) as u32
}

fn floor(scene: &mut Scene) {
    // The POV-Ray scenes have a 0.9/0.3 checker; a plain 0.9 until textures
    // land.
    let m = material(scene, Colour::splat(0.9), 0.2);
    scene.objects.push(Box::new(Plane::new(DVec3::Y, 0.0, m)));
}

fn no_constants(_: &str) -> Option<f64> {
    None
}

/// The torus scene at `size`×`size` pixels.
pub fn torus(kind: TorusKind, size: u32) -> Scene {
    let mut s = base(
        DVec3::new(0.0, 4.0, 7.0),
        DVec3::new(0.0, 0.3, 0.0),
        45.0,
        DVec3::new(5.0, 10.0, 5.0),
        size,
    );
    floor(&mut s);
    let gold = material(&mut s, Colour::new(1.0, 0.8, 0.2), 0.3);
    let lift = Transform::translate(DVec3::new(0.0, 0.5, 0.0));
    let obj: Box<dyn Shape> = match kind {
        TorusKind::Native => Box::new(Transformed::new(Box::new(Torus::new(2.0, 0.5, gold)), lift)),
        _ => {
            let consts = |n: &str| match n {
                "R" => Some(2.0),
                "r" => Some(0.5),
                _ => None,
            };
            let eq = Equation::compile("(x^2+y^2+z^2+R^2-r^2)^2 - 4R^2(x^2+y^2)", &consts)
                .expect("the benchmark torus compiles");
            let bound = (kind == TorusKind::Implicit)
                .then(|| Aabb::new(DVec3::new(-2.5, -2.5, -0.5), DVec3::new(2.5, 2.5, 0.5)));
            let xf = Transform::rotate(DVec3::X, 90.0)
                .expect("axis is non-zero")
                .then(&lift);
            Box::new(Transformed::new(
                Box::new(ImplicitSurface::new(eq, bound, gold)),
                xf,
            ))
        }
    };
    s.objects.push(obj);
    s
}

/// The heart (degree 6) scene.
pub fn sextic(size: u32) -> Scene {
    let mut s = base(
        DVec3::new(0.0, 2.6, 9.0),
        DVec3::new(0.0, 1.8, 0.0),
        38.0,
        DVec3::new(5.0, 10.0, 5.0),
        size,
    );
    floor(&mut s);
    let red = material(&mut s, Colour::new(0.9, 0.1, 0.15), 0.3);
    let eq = Equation::compile(
        "(x^2 + 9/4 y^2 + z^2 - 1)^3 - x^2 z^3 - 9/80 y^2 z^3",
        &no_constants,
    )
    .expect("the heart compiles");
    let bound = Aabb::new(DVec3::new(-1.25, -0.75, -1.05), DVec3::new(1.25, 0.75, 1.3));
    let xf = Transform::rotate(DVec3::X, -90.0)
        .expect("axis is non-zero")
        .then(&Transform::scale(DVec3::splat(1.5)).expect("non-singular"))
        .then(&Transform::translate(DVec3::new(0.0, 1.8, 0.0)));
    s.objects.push(Box::new(Transformed::new(
        Box::new(ImplicitSurface::new(eq, Some(bound), red)),
        xf,
    )));
    s
}

/// The power cube x^n + y^n + z^n = 1 (orders.sh), bounded by ±1.01.
pub fn power_cube(n: u32, size: u32) -> Scene {
    let mut s = base(
        DVec3::new(3.0, 4.0, 5.0),
        DVec3::ZERO,
        40.0,
        DVec3::new(5.0, 8.0, 6.0),
        size,
    );
    let orange = material(&mut s, Colour::new(1.0, 0.5, 0.2), 0.0);
    let text = format!("x^{n} + y^{n} + z^{n} - 1");
    let eq = Equation::compile(&text, &no_constants).expect("the power cube compiles");
    let bound = Aabb::new(DVec3::splat(-1.01), DVec3::splat(1.01));
    s.objects
        .push(Box::new(ImplicitSurface::new(eq, Some(bound), orange)));
    s
}
