/// The rendered image in linear RGB, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 3]>,
}

impl Film {
    pub fn new(width: u32, height: u32, pixels: Vec<[f32; 3]>) -> Film {
        assert_eq!(pixels.len(), (width * height) as usize);
        Film {
            width,
            height,
            pixels,
        }
    }

    pub fn get(&self, a: u32, b: u32) -> [f32; 3] {
        self.pixels[(b * self.width + a) as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn get_reads_column_a_of_row_b() {
        // Pixels in row order, row 0 at the top: pixel (a, b) is number
        // b·width + a; each holds its own coordinates here.
        let (w, h) = (5u32, 3u32);
        let pixels = (0..h)
            .flat_map(|b| (0..w).map(move |a| [a as f32, b as f32, 0.0]))
            .collect();
        let film = Film::new(w, h, pixels);
        for b in 0..h {
            for a in 0..w {
                assert_eq!(film.get(a, b), [a as f32, b as f32, 0.0]);
            }
        }
    }
}
