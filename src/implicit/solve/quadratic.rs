//! The quadratic a·t² + b·t + c = 0 without cancellation (the q-form: the
//! root of larger magnitude from q = -(b + sign(b)·√disc)/2, the other as
//! c/q, so neither subtracts nearly equal numbers). It is the one the
//! shapes use; `a = 0` falls back to the linear root.

pub fn solve_quadratic(a: f64, b: f64, c: f64) -> Option<(f64, f64)> {
    if a == 0.0 {
        if b == 0.0 {
            return None;
        }
        let t = -c / b;
        return Some((t, t));
    }
    crate::shapes::solve_quadratic(a, b, c)
}
