//! Motion blur: `render { motion_blur N  shutter S }`.
//!
//! ```text
//! render { width 320  height 240  motion_blur 8  shutter 0.5 }
//! sphere { center <-2 + 4 * clock, 0, 0>  radius 0.5 }
//! ```
//!
//! The picture is the mean of N whole pictures (sub-frames): the k-th,
//! k = 0 … N−1, is the scene built for frame `f + S·k/N` with the clock
//! that moment has (`clock + S·k/N · Δ`, Δ the clock one frame adds: 1/(last
//! − first) over a `--frames` range, 1 for a still). The shutter opens at
//! the frame's own moment, so `motion_blur 1` is exactly the unblurred
//! picture. Every camera sample of a pixel is traced once in each
//! sub-frame, with the same random numbers: the blur is the exact mean of
//! the N pictures, the same for any thread count or tiling, and anything
//! the scene moves with `clock` or `frame` (objects, lights, the camera,
//! colours) blurs. Each sub-frame costs a scene build and a render.

use crate::cli::{Args, Failure};
use crate::render::{Film, RenderStats};
use crate::scene::Scene;

/// The clock one frame adds: over the `--frames` range, 1/(last − first);
/// for a still or a one-frame range, 1 (the whole clock is one frame).
pub fn clock_per_frame(args: &Args) -> f64 {
    match &args.frames {
        Some(list) if list.len() > 1 => {
            let f = list.frames();
            1.0 / (f[f.len() - 1] as f64 - f[0] as f64)
        }
        _ => 1.0,
    }
}

/// The moments of the N sub-frames of the frame `args` names, as the
/// scene's (clock, frame).
pub fn sub_frames(args: &Args, samples: u32, shutter: f64) -> Vec<crate::FrameTime> {
    let (clock, frame) = (args.clock, args.frame.unwrap_or(0) as f64);
    let per_frame = clock_per_frame(args);
    (0..samples)
        .map(|k| {
            let dt = shutter * k as f64 / samples as f64;
            crate::FrameTime {
                clock: clock + dt * per_frame,
                frame: frame + dt,
            }
        })
        .collect()
}

/// The picture `first` (sub-frame 0, already rendered from `scene`
/// settings) averaged with the other sub-frames the scene asks for; each
/// one is built from `program` and drawn by `render`.
pub fn blur(
    args: &Args,
    program: &crate::lang::Program,
    scene: &Scene,
    first: (Film, RenderStats),
    mut render: impl FnMut(Scene) -> Result<(Film, RenderStats), Failure>,
) -> Result<(Film, RenderStats), Failure> {
    let Some(mb) = scene.settings.motion_blur.filter(|m| m.samples > 1) else {
        return Ok(first);
    };
    let (film, mut stats) = first;
    let mut sum: Vec<[f64; 3]> = film.pixels.iter().map(|p| p.map(f64::from)).collect();
    // The first sub-frame printed the scene's warnings already.
    let quiet = Args {
        quiet: true,
        ..args.clone()
    };
    for at in &sub_frames(args, mb.samples, mb.shutter)[1..] {
        let built = crate::build(&quiet, program, *at)?;
        let (w, h) = (built.scene.settings.width, built.scene.settings.height);
        if (w, h) != (scene.settings.width, scene.settings.height) {
            return Err(Failure::scene(miette::miette!(
                help = "motion blur averages pictures of one size: keep `width` and `height` \
                        independent of `clock` and `frame`",
                "the scene is {}x{} at clock {} but {w}x{h} at clock {}",
                scene.settings.width,
                scene.settings.height,
                args.clock,
                at.clock
            )));
        }
        let (sub, s) = render(built.scene)?;
        for (acc, p) in sum.iter_mut().zip(&sub.pixels) {
            for c in 0..3 {
                acc[c] += p[c] as f64;
            }
        }
        stats.seconds += s.seconds;
        stats.rays.add(&s.rays);
    }
    let n = mb.samples as f64;
    let pixels = sum.iter().map(|p| p.map(|c| (c / n) as f32)).collect();
    Ok((Film::new(film.width, film.height, pixels), stats))
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    fn args(extra: &[&str]) -> Args {
        let mut v = vec!["raytrace", "s.rt", "-o", "o.png"];
        v.extend_from_slice(extra);
        Args::parse_from(v)
    }

    #[test]
    fn the_shutter_opens_at_the_frame() {
        let a = args(&["--clock", "0.25", "--frame", "3"]);
        let t = sub_frames(&a, 4, 0.5);
        assert_eq!(t.len(), 4);
        assert_eq!((t[0].clock, t[0].frame), (0.25, 3.0));
        assert_eq!((t[2].clock, t[2].frame), (0.5, 3.25));
        assert_eq!(sub_frames(&a, 1, 0.5), [t[0]]);
    }

    #[test]
    fn over_a_range_a_sub_frame_is_a_fraction_of_a_frame() {
        // Frames 0-10: one frame is 0.1 of the clock.
        let a = Args {
            clock: 0.4,
            ..args(&["--frames", "0-10", "--frame", "4"])
        };
        let t = sub_frames(&a, 2, 1.0);
        assert!((t[1].clock - 0.45).abs() < 1e-12, "{t:?}");
        assert_eq!(t[1].frame, 4.5);
    }
}
