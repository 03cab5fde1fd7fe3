/// Rays cast, by kind (and the pixels adaptive sampling refined).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RayCounts {
    pub primary: u64,
    /// Mirror, glossy and Fresnel-reflected rays.
    pub reflected: u64,
    /// Rays refracted into or out of a dielectric.
    pub refracted: u64,
    pub shadow: u64,
    /// Shadow rays that shaft culling found clear without casting them
    /// (counted in `shadow` too: the same question, answered).
    pub settled: u64,
    /// Camera rays whose first hit was looked for among the few objects
    /// their pixel's beam meets (accel/beam.rs), not in the tree
    /// (counted in `primary` too).
    pub beamed: u64,
    /// Reflected and refracted rays not cast because their share of the
    /// pixel fell below `render { bailout }` (not counted elsewhere).
    pub bailed: u64,
    /// Pixels that adaptive sampling rendered again with more samples.
    pub refined: u64,
}

impl RayCounts {
    pub fn add(&mut self, o: &RayCounts) {
        self.primary += o.primary;
        self.reflected += o.reflected;
        self.refracted += o.refracted;
        self.shadow += o.shadow;
        self.settled += o.settled;
        self.beamed += o.beamed;
        self.bailed += o.bailed;
        self.refined += o.refined;
    }

    pub fn total(&self) -> u64 {
        self.primary + self.reflected + self.refracted + self.shadow
    }
}

#[derive(Clone, Debug, Default)]
pub struct RenderStats {
    pub seconds: f64,
    pub rays: RayCounts,
}
