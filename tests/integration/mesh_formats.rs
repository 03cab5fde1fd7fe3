//! Meshes from OBJ and STL beside PLY, end to end: one cube written in
//! four formats draws one picture, texture coordinates from OBJ's `vt`
//! drive an image as PLY's `u v` do, and a broken file is reported at its
//! line from the scene.

use miette::{Diagnostic, GraphicalReportHandler, GraphicalTheme};
use raytrace::formats::{ply, stl};
use raytrace::geometry::DVec3;
use raytrace::render::Film;
use std::path::Path;

/// The unit cube's corners and its six faces as quads wound outwards.
fn cube() -> (Vec<DVec3>, Vec<[u32; 4]>) {
    let p = (0..8)
        .map(|i| DVec3::new((i & 1) as f64, (i >> 1 & 1) as f64, (i >> 2 & 1) as f64))
        .collect();
    let quads = vec![
        [0, 2, 3, 1], // z = 0
        [4, 5, 7, 6], // z = 1
        [0, 1, 5, 4], // y = 0
        [2, 6, 7, 3], // y = 1
        [0, 4, 6, 2], // x = 0
        [1, 3, 7, 5], // x = 1
    ];
    (p, quads)
}

/// The cube as each format writes it: PLY and OBJ quads, STL triangles
/// (each quad cut as the readers cut it, a fan from its first corner).
fn cube_files() -> Vec<(&'static str, Vec<u8>)> {
    let (p, quads) = cube();
    let faces: Vec<Vec<u32>> = quads.iter().map(|q| q.to_vec()).collect();
    let ply = ply::write_ascii(&p, &faces).into_bytes();
    let mut obj = String::from("# the unit cube\no cube\n");
    for v in &p {
        obj += &format!("v {} {} {}\n", v.x, v.y, v.z);
    }
    obj += "g all\nusemtl none\n";
    for q in &quads {
        obj += &format!("f {} {} {} {}\n", q[0] + 1, q[1] + 1, q[2] + 1, q[3] + 1);
    }
    let tris: Vec<[DVec3; 3]> = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .map(|t| t.map(|k| p[k as usize]))
        .collect();
    vec![
        ("cube.ply", ply),
        ("cube.obj", obj.into_bytes()),
        ("cube_binary.stl", stl::write_binary(&tris)),
        (
            "cube_ascii.stl",
            stl::write_ascii("cube", &tris).into_bytes(),
        ),
    ]
}

fn render_with(dir: &Path, body: &str) -> Film {
    let scene = dir.join("scene.rt");
    let src = format!(
        "camera {{ position <2.2, 1.8, 3>  look_at <0.5, 0.5, 0.5>  fov 40 }}\n\
         render {{ width 64  height 48  max_depth 2 }}\n\
         light {{ position <4, 6, 5> }}\n\
         plane {{ normal <0, 1, 0>  material {{ colour rgb(0.6, 0.6, 0.6) }} }}\n{body}\n"
    );
    std::fs::write(&scene, src).unwrap();
    super::support::render_path(&scene, None, 2)
}

#[test]
fn one_cube_in_four_formats_draws_one_picture() {
    let _watchdog = crate::watchdog::start();
    let dir = tempfile::tempdir().unwrap();
    let files = cube_files();
    for (name, bytes) in &files {
        std::fs::write(dir.path().join(name), bytes).unwrap();
    }
    let empty = render_with(dir.path(), "");
    for mode in ["flat", "smooth"] {
        let films: Vec<Film> = files
            .iter()
            .map(|(name, _)| {
                render_with(
                    dir.path(),
                    &format!(
                        "mesh \"{name}\" {{ {mode}  translate <0, 0.001, 0>  \
                         material {{ colour rgb(0.8, 0.3, 0.2) }} }}"
                    ),
                )
            })
            .collect();
        // The cube is there: the middle of the picture is not the floor.
        let centre = (24 * 64 + 32) as usize;
        assert_ne!(films[0].pixels[centre], empty.pixels[centre], "{mode}");
        for (film, (name, _)) in films.iter().zip(&files) {
            assert!(
                film.pixels == films[0].pixels,
                "{name} ({mode}) differs from cube.ply"
            );
        }
    }
    // Welded STL corners make a closed cube: usable in CSG like the others.
    for (name, _) in &files {
        let d = raytrace::shapes::MeshData::load(&dir.path().join(name)).unwrap();
        assert!(d.is_closed(), "{name}");
        assert_eq!((d.vertex_count(), d.triangle_count()), (8, 12), "{name}");
    }
}

/// The unit cube as an OBJ with a `vt` per face corner: the reader
/// splits each corner into one vertex per (v, vt) pair, as every OBJ with
/// texture seams is read. The seams are not holes: it is a solid in CSG,
/// and a difference with it draws exactly what the welded PLY cube's does.
#[test]
fn a_cube_split_at_its_uv_seams_cuts_like_the_welded_cube() {
    let _watchdog = crate::watchdog::start();
    let dir = tempfile::tempdir().unwrap();
    let (p, quads) = cube();
    let mut obj = String::new();
    for v in &p {
        obj += &format!("v {} {} {}\n", v.x, v.y, v.z);
    }
    obj += "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";
    for q in &quads {
        obj += &format!(
            "f {}/1 {}/2 {}/3 {}/4\n",
            q[0] + 1,
            q[1] + 1,
            q[2] + 1,
            q[3] + 1
        );
    }
    std::fs::write(dir.path().join("seams.obj"), obj).unwrap();
    let files = cube_files();
    std::fs::write(dir.path().join("cube.ply"), &files[0].1).unwrap();
    let d = raytrace::shapes::MeshData::load(&dir.path().join("seams.obj")).unwrap();
    // One vertex per distinct (v, vt) pair: 20 of them, not the 8 corners.
    assert_eq!(
        d.vertex_count(),
        20,
        "the reader keeps one vertex per (v, vt)"
    );
    assert!(d.is_closed());
    let cut = |file: &str| {
        render_with(
            dir.path(),
            &format!(
                r#"difference {{ mesh "{file}" {{ flat }} sphere {{ centre <0.5, 0.5, 0.5>  radius 0.62 }}
                   material {{ colour rgb(0.9, 0.4, 0.1) }} }}"#
            ),
        )
    };
    let seams = cut("seams.obj");
    let welded = cut("cube.ply");
    assert!(seams.pixels == welded.pixels, "the seams change the cut");
    // And the cut is there: the sphere pokes out of every face, so the
    // difference differs from the whole cube.
    let whole = render_with(
        dir.path(),
        r#"mesh "cube.ply" { flat  material { colour rgb(0.9, 0.4, 0.1) } }"#,
    );
    let changed = whole
        .pixels
        .iter()
        .zip(&welded.pixels)
        .filter(|(a, b)| a != b)
        .count();
    assert!(changed > 100, "only {changed} pixels show the cut");
}

/// A square facing the camera, as a PLY with `u v` and as an OBJ with
/// `vt`, textured with a picture whose left half is red and right half
/// blue: both show it the same, the right way round.
#[test]
fn texture_coordinates_from_vt_drive_an_image_as_on_ply() {
    let _watchdog = crate::watchdog::start();
    let dir = tempfile::tempdir().unwrap();
    let mut img = image::RgbImage::new(2, 2);
    for y in 0..2 {
        img.put_pixel(0, y, image::Rgb([255, 0, 0]));
        img.put_pixel(1, y, image::Rgb([0, 0, 255]));
    }
    img.save(dir.path().join("halves.png")).unwrap();
    let corners = [[0, 0], [1, 0], [1, 1], [0, 1]];
    let mut ply = String::from(
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
         property float z\nproperty float u\nproperty float v\nelement face 1\n\
         property list uchar int vertex_indices\nend_header\n",
    );
    let mut obj = String::new();
    for [x, y] in corners {
        ply += &format!("{x} {y} 0 {x} {y}\n");
        obj += &format!("v {x} {y} 0\n");
    }
    ply += "4 0 1 2 3\n";
    // The texture coordinates in another order (turned by one corner), so
    // that only the indices after the slash can pair them right.
    for i in 1..=4 {
        let [x, y] = corners[i % 4];
        obj += &format!("vt {x} {y}\n");
    }
    obj += "f 1/4 2/1 3/2 4/3\n";
    std::fs::write(dir.path().join("square.ply"), ply).unwrap();
    std::fs::write(dir.path().join("square.obj"), obj).unwrap();
    let film = |name: &str| {
        let scene = dir.path().join("scene.rt");
        std::fs::write(
            &scene,
            format!(
                "camera {{ position <0.5, 0.5, 2>  look_at <0.5, 0.5, 0>  fov 40 }}\n\
                 render {{ width 32  height 32 }}\n\
                 light {{ position <0.5, 0.5, 3> }}\n\
                 mesh \"{name}\" {{ material {{ colour image \"halves.png\" }} }}\n"
            ),
        )
        .unwrap();
        super::support::render_path(&scene, None, 1)
    };
    let (a, b) = (film("square.ply"), film("square.obj"));
    assert!(
        a.pixels == b.pixels,
        "the OBJ's vt differ from the PLY's u v"
    );
    // The square spans columns 5 to 26; the image's pixel centres (u = 1/4
    // and 3/4, where the bilinear lookup is exact) fall near columns 10 and
    // 21: red on the left, blue on the right (u grows with x).
    let left = b.pixels[16 * 32 + 10];
    let right = b.pixels[16 * 32 + 21];
    assert!(left[0] > 0.9 && left[2] < 0.05, "{left:?}");
    assert!(right[2] > 0.9 && right[0] < 0.05, "{right:?}");
}

fn report(dir: &Path, mesh: &str, bytes: &[u8]) -> String {
    std::fs::write(dir.join(mesh), bytes).unwrap();
    let scene = dir.join("scene.rt");
    std::fs::write(&scene, format!("mesh \"{mesh}\" {{ flat }}\n")).unwrap();
    let program = raytrace::lang::load(&scene).unwrap();
    let Err(e) = raytrace::scene::build(&program) else {
        panic!("{mesh} built");
    };
    let mut out = String::new();
    GraphicalReportHandler::new_themed(GraphicalTheme::unicode_nocolor())
        .with_width(200)
        .render_report(&mut out, &e as &dyn Diagnostic)
        .unwrap();
    out
}

/// A broken OBJ or STL is reported from the scene's `mesh` statement with
/// the file's line and the offending text, as a broken PLY is.
#[test]
fn broken_files_are_reported_at_their_line() {
    let _watchdog = crate::watchdog::start();
    let dir = tempfile::tempdir().unwrap();
    let r = report(
        dir.path(),
        "bad.obj",
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n",
    );
    assert!(r.contains("cannot read the mesh `bad.obj` (line 4)"), "{r}");
    assert!(r.contains("vertex index 7 is out of range"), "{r}");
    assert!(r.contains("scene.rt:1:6"), "{r}");
    let r = report(
        dir.path(),
        "bad.stl",
        b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 O 0\n",
    );
    assert!(r.contains("(line 5)") && r.contains("`O`"), "{r}");
    let r = report(dir.path(), "bad.off", b"OFF\n3 1 0\n");
    assert!(r.contains(".ply, .obj or .stl"), "{r}");
}

/// The example OBJ and STL files are the solids they say: closed, wound
/// outwards (positive volume by the divergence theorem), of the right size.
#[test]
fn the_example_obj_and_stl_are_closed_outward_solids() {
    let _watchdog = crate::watchdog::start();
    let dir = super::support::project_root().join("examples/meshes");
    // (file, vertices, triangles, volume): the octahedron of circumradius
    // 1 holds 4/3; the tetrahedron inscribed in the cube [-1, 1]³ holds
    // 8/3.
    for (name, v, t, volume) in [
        ("octahedron.obj", 6, 8, 4.0 / 3.0),
        ("tetrahedron.stl", 4, 4, 8.0 / 3.0),
    ] {
        let soup = raytrace::formats::read_mesh(&dir.join(name)).unwrap();
        assert_eq!(
            (soup.positions.len(), soup.triangles.len()),
            (v, t),
            "{name}"
        );
        let signed: f64 = soup
            .triangles
            .iter()
            .map(|tri| {
                let [a, b, c] = tri.map(|k| soup.positions[k as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum();
        assert!((signed - volume).abs() < 1e-9, "{name}: {signed}");
        if let Some(n) = &soup.normals {
            // The octahedron's normals are its vertices' directions.
            for (p, n) in soup.positions.iter().zip(n) {
                assert!((*p - *n).length() < 1e-12, "{name}");
            }
        }
        let d = raytrace::shapes::MeshData::from_soup(soup);
        assert!(d.is_closed(), "{name}");
    }
}
