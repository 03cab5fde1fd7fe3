//! Frames of an animation: the `--frames` list (`1-240`, `3,5,9-20:2`),
//! the clock each frame gets, and the output name pattern `out_####.png`.
//!
//! The clock comes from the WHOLE list, never from the part one task
//! renders: the lowest frame has clock 0, the highest clock 1, and the
//! others lie in proportion to their numbers between them
//! (`clock = (frame − first) / (last − first)`), so a frame rendered alone
//! is the same picture as that frame of the whole run. A list of a single
//! frame has clock 0 (there is no span to spread it over).

use std::path::{Path, PathBuf};

/// The most frames one `--frames` list may name: far more than any
/// animation, and few enough that the list is cheap to hold.
pub const MAX_FRAMES: u64 = 1_000_000;

/// A sorted list of distinct frame numbers, as `--frames` wrote them.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FrameList {
    frames: Vec<u32>,
}

impl FrameList {
    /// `1-240`, `3,5,9-20:2`, `7`: pieces separated by commas, each a
    /// frame, a range `A-B` (both included, A ≤ B) or a range with a step
    /// `A-B:S` (A, A+S, … up to B). A frame named twice counts once.
    pub fn parse(s: &str) -> Result<FrameList, String> {
        let example = "write e.g. `1-240`, `3,5,9-20:2` or `7`";
        if s.trim().is_empty() {
            return Err(format!("the frame list is empty: {example}"));
        }
        let mut frames = Vec::new();
        let mut total: u64 = 0;
        for piece in s.split(',').map(str::trim) {
            let (range, step) = match piece.split_once(':') {
                Some((r, st)) => (r.trim(), Some(st.trim())),
                None => (piece, None),
            };
            let number = |t: &str| {
                t.trim()
                    .parse::<u32>()
                    .map_err(|_| format!("`{t}` in `{s}` is not a frame number (0 or more)"))
            };
            if range.is_empty() {
                return Err(format!("`{s}` has an empty piece: {example}"));
            }
            let (a, b) = match range.split_once('-') {
                Some((a, b)) => (number(a)?, number(b)?),
                None => {
                    let a = number(range)?;
                    (a, a)
                }
            };
            if a > b {
                return Err(format!(
                    "the range `{range}` in `{s}` runs backwards: write the lower frame first (`{b}-{a}`)"
                ));
            }
            let step = match step {
                None => 1,
                Some(t) => match t.parse::<u32>() {
                    Ok(0) => {
                        return Err(format!(
                            "the step of `{piece}` in `{s}` is 0: a step is 1 or more"
                        ));
                    }
                    Ok(n) => n,
                    Err(_) => {
                        return Err(format!(
                            "the step `{t}` in `{s}` is not a whole number (1 or more)"
                        ));
                    }
                },
            };
            // Counted before the frames are made, so that `0-4000000000`
            // is refused without filling memory.
            total += (b - a) as u64 / step as u64 + 1;
            if total > MAX_FRAMES {
                return Err(format!(
                    "`{s}` names more than {MAX_FRAMES} frames; render an animation in several runs"
                ));
            }
            frames.extend(
                (a as u64..=b as u64)
                    .step_by(step as usize)
                    .map(|f| f as u32),
            );
        }
        frames.sort_unstable();
        frames.dedup();
        Ok(FrameList { frames })
    }

    /// A single frame (a still is the list of its one frame).
    pub fn single(frame: u32) -> FrameList {
        FrameList {
            frames: vec![frame],
        }
    }

    pub fn frames(&self) -> &[u32] {
        &self.frames
    }

    pub fn len(&self) -> usize {
        self.frames.len()
    }

    pub fn is_empty(&self) -> bool {
        self.frames.is_empty()
    }

    pub fn contains(&self, frame: u32) -> bool {
        self.frames.binary_search(&frame).is_ok()
    }

    /// The clock of `frame`: 0 at the list's first frame, 1 at its last,
    /// linear in the frame number between; 0 when the list has one frame.
    pub fn clock(&self, frame: u32) -> f64 {
        let (first, last) = (self.frames[0], self.frames[self.frames.len() - 1]);
        if last == first {
            0.0
        } else {
            (frame as f64 - first as f64) / (last as f64 - first as f64)
        }
    }

    /// The frames of the list's range as `first-last` (with its count), for
    /// messages.
    pub fn describe(&self) -> String {
        let (first, last) = (self.frames[0], self.frames[self.frames.len() - 1]);
        if first == last {
            format!("frame {first}")
        } else {
            format!("frames {first}-{last} ({} frames)", self.frames.len())
        }
    }
}

/// Where in a file name the frame number goes: the one run of `#` in its
/// last component, replaced by the frame number padded with zeros to the
/// run's length (`out_####.png`, frame 7: `out_0007.png`; a number longer
/// than the run is written whole).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OutputPattern {
    path: PathBuf,
}

impl OutputPattern {
    pub fn new(path: &Path) -> OutputPattern {
        OutputPattern {
            path: path.to_owned(),
        }
    }

    /// Whether the name has a frame run (`#`) and a tile run (`@`), and a
    /// message when either appears more than once.
    fn runs(&self) -> Result<(bool, bool), String> {
        let name = self.name();
        let mut has = [false, false];
        for (i, c) in ['#', '@'].into_iter().enumerate() {
            let runs = name
                .split(|x| x != c)
                .filter(|piece| !piece.is_empty())
                .count();
            if runs > 1 {
                return Err(format!(
                    "the output name `{name}` has {runs} runs of `{c}`; write one (e.g. `out_{}.png`)",
                    if c == '#' { "####" } else { "@@" }
                ));
            }
            has[i] = runs == 1;
        }
        Ok((has[0], has[1]))
    }

    fn name(&self) -> String {
        self.path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    }

    /// Checks the name can hold every picture the run makes: a `#` run
    /// when the animation has more than one frame, an `@` run when one
    /// process writes more than one tile.
    pub fn check(&self, frames: usize, tiles_per_process: usize) -> Result<(), String> {
        let (hash, at) = self.runs()?;
        if frames > 1 && !hash {
            return Err(format!(
                "{frames} frames would all be written to `{}`: put `####` in the name where the \
                 frame number goes, e.g. `-o out_####.png`",
                self.path.display()
            ));
        }
        if tiles_per_process > 1 && !at {
            return Err(format!(
                "{tiles_per_process} tiles would all be written to `{}`: put `@@` in the name \
                 where the tile number goes, e.g. `-o tile_@@.png`",
                self.path.display()
            ));
        }
        Ok(())
    }

    /// The name of `frame` (and `tile`, where the name has a tile run).
    pub fn expand(&self, frame: u32, tile: Option<u32>) -> PathBuf {
        let name = self.name();
        let mut out = String::with_capacity(name.len() + 8);
        let mut chars = name.chars().peekable();
        while let Some(c) = chars.next() {
            if c == '#' || c == '@' {
                let mut width = 1;
                while chars.peek() == Some(&c) {
                    chars.next();
                    width += 1;
                }
                let n = if c == '#' { Some(frame) } else { tile };
                match n {
                    Some(n) => out.push_str(&format!("{n:0width$}")),
                    None => out.extend(std::iter::repeat_n(c, width)),
                }
            } else {
                out.push(c);
            }
        }
        self.path.with_file_name(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn list(s: &str) -> Vec<u32> {
        FrameList::parse(s).unwrap().frames().to_vec()
    }

    #[test]
    fn lists_ranges_and_steps() {
        assert_eq!(list("1-5"), [1, 2, 3, 4, 5]);
        assert_eq!(list("3,5,9-20:2"), [3, 5, 9, 11, 13, 15, 17, 19]);
        assert_eq!(list("7"), [7]);
        assert_eq!(list(" 4 , 2-3 "), [2, 3, 4]);
        // Named twice, counted once.
        assert_eq!(list("1-3,2"), [1, 2, 3]);
        assert_eq!(list("0-10:5"), [0, 5, 10]);
    }

    #[test]
    fn bad_lists_say_why() {
        for (s, words) in [
            ("", "empty"),
            ("5-1", "backwards"),
            ("1-5:0", "step"),
            ("1-5:x", "step"),
            ("1,,2", "empty piece"),
            ("a-3", "not a frame number"),
            ("-3", "not a frame number"),
            ("0-4000000000", "more than"),
        ] {
            let e = FrameList::parse(s).unwrap_err();
            assert!(e.contains(words), "`{s}`: {e}");
        }
    }

    #[test]
    fn the_clock_spans_the_whole_list() {
        let l = FrameList::parse("1-241").unwrap();
        assert_eq!(l.clock(1), 0.0);
        assert_eq!(l.clock(241), 1.0);
        assert_eq!(l.clock(121), 0.5);
        // A stepped list: by frame number, from its lowest to its highest.
        let l = FrameList::parse("3,5,9-19:2").unwrap();
        assert_eq!(l.clock(3), 0.0);
        assert_eq!(l.clock(11), 0.5);
        assert_eq!(l.clock(19), 1.0);
        assert_eq!(FrameList::single(9).clock(9), 0.0);
    }

    #[test]
    fn patterns_pad_the_frame_number() {
        let p = OutputPattern::new(Path::new("dir/out_####.png"));
        assert_eq!(p.expand(7, None), Path::new("dir/out_0007.png"));
        assert_eq!(p.expand(123456, None), Path::new("dir/out_123456.png"));
        let p = OutputPattern::new(Path::new("t_@@_f#.exr"));
        assert_eq!(p.expand(3, Some(5)), Path::new("t_05_f3.exr"));
        // A `#` in a folder name is not a frame run.
        let p = OutputPattern::new(Path::new("a#b/out.png"));
        assert_eq!(p.expand(3, None), Path::new("a#b/out.png"));
        assert!(p.check(2, 1).unwrap_err().contains("####"));
        assert!(p.check(1, 1).is_ok());
        let p = OutputPattern::new(Path::new("o_##_##.png"));
        assert!(p.check(2, 1).unwrap_err().contains("2 runs"));
        let p = OutputPattern::new(Path::new("o_##.png"));
        assert!(p.check(5, 2).unwrap_err().contains("@@"));
    }
}
