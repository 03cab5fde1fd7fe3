//! Materials as the integrator meets them: one file per kind, each saying
//! what that part reflects, transmits or emits at a shading point. The
//! integrator adds the parts a material has; none of these files knows the
//! others.
//!
//! Notation (conventions.md, "Round 2"): d the incoming ray direction, n the
//! unit normal turned to face the ray, v = −d toward the eye, l toward the
//! light, E the light's colour × intensity, (a)⁺ = max(0, a).

pub mod dielectric;
pub mod emissive;
pub mod glossy;
pub mod matte;
pub mod mirror;
pub mod phong;
