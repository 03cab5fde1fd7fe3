//! The parameters each kind of block accepts, for tools that are not the
//! builder (the language server's completion and hover): read from the
//! same schemas the builder checks blocks against, so that what an editor
//! offers is exactly what `raytrace` accepts.

use super::objects;
use super::params::{self, Schema};
use super::patterns;

/// A parameter a block accepts: its name and what its values should be
/// (the words of the builder's "expected …" messages).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamInfo {
    pub name: &'static str,
    pub expects: &'static str,
}

/// The parameters of the block written after `block`, inside a block
/// written after `parent` (`refract` inside `material`, `checker` after
/// `colour`): `None` when `block` names no kind of block. Objects list
/// their own parameters, then `material` and the transforms; `group` and
/// the CSG operations also the objects they may hold.
pub fn block_parameters(block: &str, parent: Option<&str>) -> Option<Vec<ParamInfo>> {
    let owned;
    let schema: &Schema = match (block, parent) {
        ("camera", _) => &params::CAMERA,
        ("render", _) => &params::RENDER,
        ("adaptive", _) => &params::ADAPTIVE,
        ("light", _) => &params::LIGHT,
        ("material", _) => &params::MATERIAL,
        ("refract", _) => &params::REFRACT,
        ("environment", _) => &params::ENVIRONMENT,
        ("occlusion", _) => &params::OCCLUSION,
        (b, _) if objects::is_object(b) => {
            owned = objects::schema(b);
            &owned
        }
        (b, _) if patterns::NORMALS.contains(&b) => &patterns::NORMAL,
        (b, _) if crate::scene::pattern::NAMES.contains(&b) => patterns::schema_of(b),
        _ => return None,
    };
    let mut out: Vec<ParamInfo> = Vec::new();
    for name in schema.names() {
        let expects = schema.get(name).map_or("an object", |s| s.expects);
        out.push(ParamInfo { name, expects });
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(block: &str) -> Vec<&'static str> {
        block_parameters(block, None)
            .unwrap()
            .iter()
            .map(|p| p.name)
            .collect()
    }

    #[test]
    fn objects_list_their_own_then_material_and_transforms() {
        let s = names("sphere");
        assert_eq!(&s[..3], ["centre", "radius", "samples"]);
        assert!(s.contains(&"material") && s.contains(&"rotate"));
        assert!(!s.contains(&"sphere"), "a sphere holds no objects");
        assert!(names("union").contains(&"sphere"));
    }

    #[test]
    fn blocks_inside_blocks_and_patterns_have_their_parameters() {
        assert!(names("refract").contains(&"ior"));
        assert!(names("adaptive").contains(&"max_samples"));
        assert!(names("checker3d").contains(&"size"));
        assert!(names("bumps").contains(&"amount"));
        assert!(block_parameters("radius", None).is_none());
    }

    #[test]
    fn each_parameter_says_what_it_expects() {
        let r = block_parameters("torus", None).unwrap();
        assert_eq!(
            r[0],
            ParamInfo {
                name: "major",
                expects: "a number"
            }
        );
    }
}
