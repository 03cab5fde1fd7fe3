//! AST → Scene. (Placeholder until the front end lands.)

use super::Scene;
use crate::lang::Program;

pub fn build(_program: &Program) -> miette::Result<Scene> {
    Err(miette::miette!("scene building is not written yet"))
}
