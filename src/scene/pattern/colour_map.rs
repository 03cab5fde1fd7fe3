//! `colour_map { 0 #303030  0.6 #808080  1 white }`: a pattern's value
//! turned into a colour, piecewise linear between sorted keys in [0, 1].
//! Below the first key the first colour holds, above the last the last;
//! `a`/`b` are the two-entry map `{ 0 a  1 b }`.
//!
//! Between keys kᵢ ≤ f ≤ kᵢ₊₁: c = cᵢ·(1 − s) + cᵢ₊₁·s, s = (f − kᵢ)/(kᵢ₊₁ − kᵢ)
//! (glam's `lerp`, exact at both ends, so a checker's 0 and 1 give `a` and
//! `b` exactly). Two equal keys make a sharp step.

use super::Colour;

#[derive(Clone, Debug, PartialEq)]
pub struct ColourMap {
    /// Sorted by key, at least one entry.
    keys: Vec<(f64, Colour)>,
}

/// Why a list of keys is not a map (the builder adds the span).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapError {
    Empty,
    /// The entry at this index is outside [0, 1].
    OutOfRange(usize),
    /// The entry at this index is smaller than the one before.
    Unsorted(usize),
}

impl ColourMap {
    pub fn new(keys: Vec<(f64, Colour)>) -> Result<ColourMap, MapError> {
        if keys.is_empty() {
            return Err(MapError::Empty);
        }
        for (i, (k, _)) in keys.iter().enumerate() {
            if !(0.0..=1.0).contains(k) {
                return Err(MapError::OutOfRange(i));
            }
            if i > 0 && *k < keys[i - 1].0 {
                return Err(MapError::Unsorted(i));
            }
        }
        Ok(ColourMap { keys })
    }

    /// `a` at 0, `b` at 1.
    pub fn two(a: Colour, b: Colour) -> ColourMap {
        ColourMap {
            keys: vec![(0.0, a), (1.0, b)],
        }
    }

    pub fn at(&self, f: f64) -> Colour {
        let (first, last) = (self.keys[0], self.keys[self.keys.len() - 1]);
        if f <= first.0 {
            return first.1;
        }
        if f >= last.0 {
            return last.1;
        }
        // The first key above f; the one before it is at or below.
        let i = self.keys.partition_point(|(k, _)| *k <= f);
        let (k0, c0) = self.keys[i - 1];
        let (k1, c1) = self.keys[i];
        c0.lerp(c1, (f - k0) / (k1 - k0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RED: Colour = Colour::new(1.0, 0.0, 0.0);
    const BLUE: Colour = Colour::new(0.0, 0.0, 1.0);
    const GREY: Colour = Colour::new(0.5, 0.5, 0.5);

    #[test]
    fn two_keys_are_exactly_a_and_b_at_the_ends_and_linear_between() {
        let m = ColourMap::two(RED, BLUE);
        assert_eq!(m.at(0.0), RED);
        assert_eq!(m.at(1.0), BLUE);
        assert_eq!(m.at(0.25), RED.lerp(BLUE, 0.25));
        assert_eq!(m.at(-3.0), RED);
        assert_eq!(m.at(7.0), BLUE);
    }

    #[test]
    fn three_keys_are_piecewise_linear() {
        let m = ColourMap::new(vec![(0.2, RED), (0.6, GREY), (1.0, BLUE)]).unwrap();
        assert_eq!(m.at(0.1), RED, "below the first key: the first colour");
        assert_eq!(m.at(0.6), GREY);
        assert!((m.at(0.4) - RED.lerp(GREY, 0.5)).abs().max_element() < 1e-12);
        assert!((m.at(0.8) - GREY.lerp(BLUE, 0.5)).abs().max_element() < 1e-12);
    }

    #[test]
    fn equal_keys_make_a_step() {
        let m = ColourMap::new(vec![(0.0, RED), (0.5, RED), (0.5, BLUE), (1.0, BLUE)]).unwrap();
        assert_eq!(m.at(0.4999), RED);
        assert_eq!(m.at(0.5), BLUE);
    }

    #[test]
    fn bad_keys_are_refused() {
        assert_eq!(ColourMap::new(vec![]), Err(MapError::Empty));
        assert_eq!(
            ColourMap::new(vec![(0.0, RED), (1.5, BLUE)]),
            Err(MapError::OutOfRange(1))
        );
        assert_eq!(
            ColourMap::new(vec![(0.6, RED), (0.2, BLUE)]),
            Err(MapError::Unsorted(1))
        );
        assert_eq!(
            ColourMap::new(vec![(f64::NAN, RED)]),
            Err(MapError::OutOfRange(0))
        );
    }
}
