use glam::DVec3;

/// A ray `origin + t·dir`. World rays have a unit `dir`; rays moved into an
/// object's own space by a transform keep the same `t` and so, in general,
/// a direction that is *not* unit length. Every shape must accept that.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: DVec3,
    pub dir: DVec3,
}

impl Ray {
    pub fn new(origin: DVec3, dir: DVec3) -> Self {
        Ray { origin, dir }
    }

    pub fn at(&self, t: f64) -> DVec3 {
        self.origin + t * self.dir
    }
}
