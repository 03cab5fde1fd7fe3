//! Tiles: a picture cut into N rectangles on a grid, for `--tile I/N` and
//! `--tiles N --task-index I`.
//!
//! The grid is the one of N = columns × rows whose tiles are the most
//! square: it minimises |ln(tile width / tile height)|, with fewer columns
//! winning a tie. Column edges fall at `floor(i·W / columns)` and row edges
//! at `floor(j·H / rows)`, so the tiles meet without gaps or overlaps and
//! differ in size by at most a pixel. Tiles are numbered row by row from
//! the top left, from 0.

use crate::render::Region;

/// A grid of `columns` × `rows` tiles over a `width` × `height` picture.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Grid {
    pub width: u32,
    pub height: u32,
    pub columns: u32,
    pub rows: u32,
}

impl Grid {
    /// The most square grid of exactly `n` tiles, each at least one pixel.
    pub fn new(width: u32, height: u32, n: u32) -> Result<Grid, String> {
        if n == 0 {
            return Err("a picture cannot be cut into 0 tiles".into());
        }
        let mut best: Option<(f64, Grid)> = None;
        // At most one column a pixel: the loop is bounded by the width,
        // not by N (`--tile 0/4000000000` answers at once).
        for columns in 1..=n.min(width) {
            if !n.is_multiple_of(columns) {
                continue;
            }
            let rows = n / columns;
            if columns > width || rows > height {
                continue;
            }
            let aspect = (width as f64 / columns as f64) / (height as f64 / rows as f64);
            let cost = aspect.ln().abs();
            if best.as_ref().is_none_or(|(c, _)| cost < *c - 1e-12) {
                best = Some((
                    cost,
                    Grid {
                        width,
                        height,
                        columns,
                        rows,
                    },
                ));
            }
        }
        best.map(|(_, g)| g).ok_or_else(|| {
            format!(
                "a {width}x{height} picture cannot be cut into {n} tiles of at least one pixel \
                 (no grid of columns × rows = {n} fits)"
            )
        })
    }

    pub fn count(&self) -> u32 {
        self.columns * self.rows
    }

    /// Tile `i` (0-based, row by row) in the full picture's pixels.
    pub fn tile(&self, i: u32) -> Region {
        let (c, r) = (i % self.columns, i / self.columns);
        let edge = |k: u32, side: u32, n: u32| (k as u64 * side as u64 / n as u64) as u32;
        let (x0, x1) = (
            edge(c, self.width, self.columns),
            edge(c + 1, self.width, self.columns),
        );
        let (y0, y1) = (
            edge(r, self.height, self.rows),
            edge(r + 1, self.height, self.rows),
        );
        Region {
            x: x0,
            y: y0,
            width: x1 - x0,
            height: y1 - y0,
        }
    }
}

/// `--tile I/N` as written: tile I of N (I counted from the index base).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TileArg {
    pub index: u32,
    pub count: u32,
}

/// `I/N`: two whole numbers.
pub fn parse_tile(s: &str) -> Result<TileArg, String> {
    let bad = || format!("`{s}`: write the tile as I/N, e.g. `--tile 0/4` for the first of 4");
    let (i, n) = s.split_once('/').ok_or_else(bad)?;
    let index = i.trim().parse::<u32>().map_err(|_| bad())?;
    let count = n.trim().parse::<u32>().map_err(|_| bad())?;
    if count == 0 {
        return Err(format!("`{s}`: a picture cannot be cut into 0 tiles"));
    }
    Ok(TileArg { index, count })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_are_the_most_square() {
        let g = Grid::new(48, 32, 4).unwrap();
        assert_eq!((g.columns, g.rows), (2, 2));
        let g = Grid::new(48, 32, 6).unwrap();
        assert_eq!((g.columns, g.rows), (3, 2)); // 16x16 tiles
        let g = Grid::new(1000, 10, 4).unwrap();
        assert_eq!((g.columns, g.rows), (4, 1));
        let g = Grid::new(48, 32, 7).unwrap();
        assert_eq!((g.columns, g.rows), (7, 1));
        let g = Grid::new(3, 100, 7).unwrap();
        assert_eq!((g.columns, g.rows), (1, 7));
        assert!(Grid::new(2, 2, 5).is_err());
        assert!(Grid::new(48, 32, u32::MAX).is_err());
        assert!(Grid::new(0, 32, 4).is_err());
        assert!(Grid::new(2, 2, 0).is_err());
    }

    #[test]
    fn tiles_cover_every_pixel_exactly_once() {
        for (w, h, n) in [
            (48, 32, 4),
            (48, 32, 6),
            (37, 23, 12),
            (5, 3, 15),
            (100, 1, 7),
        ] {
            let g = Grid::new(w, h, n).unwrap();
            let mut hits = vec![0u8; (w * h) as usize];
            for i in 0..g.count() {
                let t = g.tile(i);
                assert!(t.width > 0 && t.height > 0, "{w}x{h}/{n} tile {i}: {t:?}");
                for y in t.y..t.y + t.height {
                    for x in t.x..t.x + t.width {
                        hits[(y * w + x) as usize] += 1;
                    }
                }
            }
            assert!(hits.iter().all(|&k| k == 1), "{w}x{h} in {n} tiles");
        }
    }

    #[test]
    fn tile_arguments() {
        assert_eq!(parse_tile("2/4").unwrap(), TileArg { index: 2, count: 4 });
        assert!(parse_tile("2").is_err());
        assert!(parse_tile("2/0").is_err());
        assert!(parse_tile("-1/4").is_err());
    }
}
