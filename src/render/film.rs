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
