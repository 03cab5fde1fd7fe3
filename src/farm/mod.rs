//! Renders a farm can split: the frames of an animation, chunks of them
//! for the tasks of a job array, tiles of a picture, and `raytrace merge`
//! to put tiles back together. docs/farm.md has the recipes.
//!
//! - `frames`: `--frames 1-240`, the clock of each frame, `out_####.png`;
//! - `tiles`: the grid of `--tile I/N` and `--tiles N`;
//! - `stamp`, `image_io`: what a region's image records, PNG and EXR;
//! - `merge`: `raytrace merge TILES... -o full.png`;
//! - `motion`: `render { motion_blur N  shutter S }`;
//! - `log`: `--log json`.
//!
//! Every pixel is a pure function of its place in the full picture and of
//! the frame (see `render`), so a tile is exactly those pixels of the full
//! render, a frame rendered alone is that frame of the range, and a merge
//! is byte for byte the full picture.

pub mod frames;
pub mod image_io;
pub mod log;
pub mod merge;
pub mod motion;
pub mod stamp;
pub mod tiles;

pub use merge::merge_main;

use crate::cli::{Args, Failure, RegionArg};
use crate::{FrameTime, Timings};
use frames::{FrameList, OutputPattern};
use std::time::{Duration, Instant};

/// Whether the command line asks for more than one plain picture: frames,
/// a task's share, a tile, skipping or a log.
pub fn wanted(args: &Args) -> bool {
    args.frames.is_some()
        || args.task_index.is_some()
        || args.tile.is_some()
        || args.skip_existing
        || args.log.is_some()
}

/// One picture this process renders: a frame, and maybe one tile of it
/// (0-based).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Job {
    pub frame: u32,
    pub clock: f64,
    pub tile: Option<u32>,
}

/// What this process renders, from the command line alone (before the
/// scene is read, so that a mistake costs nothing).
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    pub jobs: Vec<Job>,
    /// The tile count, when rendering tiles.
    pub tiles: Option<u32>,
}

impl Plan {
    pub fn new(args: &Args) -> Result<Plan, String> {
        let base = args.index_base as u64;
        let all = args
            .frames
            .clone()
            .unwrap_or_else(|| FrameList::single(args.frame.unwrap_or(0)));
        let mut frames: Vec<u32> = match (&args.frames, args.frame) {
            (Some(list), Some(f)) if !list.contains(f) => {
                return Err(format!(
                    "frame {f} is not one of the animation's {}",
                    list.describe()
                ));
            }
            (Some(_), Some(f)) => vec![f],
            _ => all.frames().to_vec(),
        };
        let mut tile = None;
        let mut tiles = None;
        if let Some(t) = args.tile {
            let i = (t.index as u64)
                .checked_sub(base)
                .filter(|&i| i < t.count as u64)
                .ok_or_else(|| {
                    format!(
                        "there is no tile {} of {}: with --index-base {base} they are numbered \
                         {base} to {}",
                        t.index,
                        t.count,
                        t.count as u64 - 1 + base
                    )
                })?;
            tile = Some(i as u32);
            tiles = Some(t.count);
        }
        if let Some(given) = args.task_index {
            let i = given
                .checked_sub(base)
                .ok_or_else(|| format!("--task-index {given} is below --index-base {base}"))?;
            let len = frames.len() as u64;
            let shown = |i: u64| i + base;
            match (args.tasks, args.frames_per_task, args.tiles) {
                (Some(n), None, None) => {
                    if n > len {
                        return Err(format!(
                            "{n} tasks cannot share {len} frame{}: ask for at most {len} tasks",
                            if len == 1 { "" } else { "s" }
                        ));
                    }
                    if i >= n {
                        return Err(format!(
                            "--task-index {given} is past the last of {n} tasks ({})",
                            shown(n - 1)
                        ));
                    }
                    // Contiguous chunks whose sizes differ by at most one.
                    let (a, b) = (i * len / n, (i + 1) * len / n);
                    frames = frames[a as usize..b as usize].to_vec();
                }
                (None, Some(k), None) => {
                    let a = i.checked_mul(k).filter(|&a| a < len).ok_or_else(|| {
                        format!(
                            "--task-index {given} is past the last task: {len} frames at {k} a \
                             task make {} tasks ({} to {})",
                            len.div_ceil(k),
                            shown(0),
                            shown(len.div_ceil(k) - 1)
                        )
                    })?;
                    frames = frames[a as usize..(a + k).min(len) as usize].to_vec();
                }
                (None, None, Some(t)) => {
                    let units = len * t as u64;
                    if i >= units {
                        return Err(format!(
                            "--task-index {given} is past the last task: {len} frame{} of {t} \
                             tiles make {units} tasks ({} to {})",
                            if len == 1 { "" } else { "s" },
                            shown(0),
                            shown(units - 1)
                        ));
                    }
                    frames = vec![frames[(i / t as u64) as usize]];
                    tile = Some((i % t as u64) as u32);
                    tiles = Some(t);
                }
                _ => {
                    return Err(
                        "--task-index needs --tasks N, --frames-per-task K or --tiles N to say \
                         what a task renders"
                            .into(),
                    );
                }
            }
        }
        if let Some(out) = &args.output {
            OutputPattern::new(out).check(all.len(), 1)?;
        }
        let jobs = frames
            .into_iter()
            .map(|frame| Job {
                frame,
                clock: if args.frames.is_some() {
                    all.clock(frame)
                } else {
                    args.clock
                },
                tile,
            })
            .collect();
        Ok(Plan { jobs, tiles })
    }
}

/// Renders the frames and tiles the command line asks for: parsed once,
/// built and rendered per frame.
pub fn run(args: &Args) -> Result<(), Failure> {
    let mut current = args.clone();
    let result = run_jobs(args, &mut current);
    if let Err(f) = &result {
        log::failed(&current, f.exit as i32, &f.report.to_string());
    }
    result
}

fn run_jobs(args: &Args, current: &mut Args) -> Result<(), Failure> {
    let start = Instant::now();
    let plan = Plan::new(args).map_err(|e| Failure::usage(miette::miette!("{e}")))?;
    crate::check_output_name(args)?;
    let program = crate::load(args)?;
    let mut parse = start.elapsed();
    let pattern = args.output.as_deref().map(OutputPattern::new);
    let base = args.index_base as u32;
    for job in &plan.jobs {
        let job_start = Instant::now();
        *current = Args {
            clock: job.clock,
            frame: Some(job.frame),
            ..args.clone()
        };
        let out = pattern
            .as_ref()
            .map(|p| p.expand(job.frame, job.tile.map(|t| t + base)));
        if let Some(path) = &out
            && args.skip_existing
            && path.exists()
        {
            log::skipped(current, path);
            continue;
        }
        let at = FrameTime {
            clock: job.clock,
            frame: job.frame as f64,
        };
        let built = crate::build(current, &program, at)?;
        if let (Some(i), Some(n)) = (job.tile, plan.tiles) {
            let s = &built.scene.settings;
            let grid = tiles::Grid::new(s.width, s.height, n)
                .map_err(|e| Failure::usage(miette::miette!("{e}")))?;
            let r = grid.tile(i);
            current.region = Some(RegionArg::Pixels([r.x, r.x + r.width, r.y, r.y + r.height]));
        }
        if args.check {
            if !args.quiet {
                println!("frame {}: ok", job.frame);
            }
            continue;
        }
        let Some(path) = out else { continue };
        let timings = Timings {
            start: job_start,
            parse: std::mem::replace(&mut parse, Duration::ZERO),
            build: job_start.elapsed(),
        };
        crate::render_to(current, &program, built.scene, &path, timings)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    fn plan(extra: &[&str]) -> Result<Plan, String> {
        let mut v = vec!["raytrace", "s.rt", "-o", "o_####.png"];
        v.extend_from_slice(extra);
        Plan::new(&Args::try_parse_from(v).map_err(|e| e.to_string())?)
    }

    fn frames(p: &Plan) -> Vec<u32> {
        p.jobs.iter().map(|j| j.frame).collect()
    }

    #[test]
    fn tasks_take_contiguous_chunks_of_the_whole_range() {
        let mut seen = vec![];
        for i in 0..3 {
            let p = plan(&[
                "--frames",
                "1-10",
                "--tasks",
                "3",
                "--task-index",
                &i.to_string(),
            ])
            .unwrap();
            // The clock is the whole range's, whatever the chunk.
            for j in &p.jobs {
                assert_eq!(j.clock, (j.frame - 1) as f64 / 9.0);
            }
            seen.extend(frames(&p));
        }
        assert_eq!(seen, (1..=10).collect::<Vec<_>>());
        let p = plan(&[
            "--frames",
            "1-10",
            "--frames-per-task",
            "4",
            "--task-index",
            "2",
        ])
        .unwrap();
        assert_eq!(frames(&p), [9, 10]);
        // 1-based, as SGE counts.
        let p = plan(&[
            "--frames",
            "1-10",
            "--frames-per-task",
            "4",
            "--task-index",
            "1",
            "--index-base",
            "1",
        ])
        .unwrap();
        assert_eq!(frames(&p), [1, 2, 3, 4]);
    }

    #[test]
    fn tasks_of_tiles_walk_frames_then_tiles() {
        let p = plan(&["--frames", "5-7", "--tiles", "4", "--task-index", "6"]).unwrap();
        assert_eq!(
            p.jobs,
            [Job {
                frame: 6,
                clock: 0.5,
                tile: Some(2)
            }]
        );
        assert_eq!(p.tiles, Some(4));
        let p = plan(&["--tile", "3/4"]).unwrap();
        assert_eq!(
            p.jobs,
            [Job {
                frame: 0,
                clock: 0.0,
                tile: Some(3)
            }]
        );
        let p = plan(&["--tile", "4/4", "--index-base", "1"]).unwrap();
        assert_eq!(p.jobs[0].tile, Some(3));
    }

    #[test]
    fn one_frame_of_a_range_keeps_the_range_clock() {
        let p = plan(&["--frames", "0-4", "--frame", "3"]).unwrap();
        assert_eq!(
            p.jobs,
            [Job {
                frame: 3,
                clock: 0.75,
                tile: None
            }]
        );
    }

    #[test]
    fn mistakes_are_refused_before_any_work() {
        for (extra, words) in [
            (&["--frames", "0-4", "--frame", "9"][..], "not one of"),
            (
                &["--frames", "1-3", "--tasks", "4", "--task-index", "0"],
                "at most 3 tasks",
            ),
            (
                &["--frames", "1-6", "--tasks", "3", "--task-index", "3"],
                "past the last",
            ),
            (
                &[
                    "--frames",
                    "1-6",
                    "--frames-per-task",
                    "2",
                    "--task-index",
                    "3",
                ],
                "past the last",
            ),
            (&["--tiles", "4", "--task-index", "4"], "past the last"),
            (&["--tile", "4/4"], "no tile 4 of 4"),
            (&["--tile", "0/4", "--index-base", "1"], "no tile 0"),
            (&["--task-index", "0"], "needs --tasks"),
            (
                &["--task-index", "0", "--tasks", "1", "--index-base", "1"],
                "below",
            ),
        ] {
            let e = plan(extra).unwrap_err();
            assert!(e.contains(words), "{extra:?}: {e}");
        }
        // Clap's own conflicts.
        assert!(plan(&["--frames", "1-3", "--clock", "0.5"]).is_err());
        assert!(plan(&["--tile", "0/2", "--region", "0,1,0,1"]).is_err());
        assert!(plan(&["--tasks", "2"]).is_err());
        // Several frames need a `#` run in the name.
        let a =
            Args::try_parse_from(["raytrace", "s.rt", "-o", "o.png", "--frames", "1-2"]).unwrap();
        assert!(Plan::new(&a).unwrap_err().contains("####"));
    }
}
