//! The record a region's image carries so that `raytrace merge` can place
//! it and check it belongs with the others: where it lies in which full
//! picture, which scene and settings made it, which frame and clock, and
//! the transfer curve (to turn linear EXR tiles into a PNG).
//!
//! It is one line of `key=value` words, stored in a PNG `tEXt` chunk and
//! in an EXR header attribute, both named [`KEY`]:
//!
//! ```text
//! v=1 full=48x32 region=24,0,24,16 scene=9f0c…e1 frame=3 clock=0.25 transfer=srgb
//! ```
//!
//! `region` is x, y, width, height in the full picture's pixels. `scene` is
//! a 64-bit FNV-1a hash of the scene's text (with its includes) and of the
//! command-line settings that change the picture (`-D`, `--width`,
//! `--height`, `--samples`); threads and the region do not enter it.

use crate::cli::Args;
use crate::render::Region;
use crate::scene::Transfer;

/// The PNG text keyword and EXR attribute name of the record.
pub const KEY: &str = "raytrace";

/// Where a picture's pixels lie and what made them.
#[derive(Clone, Debug, PartialEq)]
pub struct Stamp {
    pub full_width: u32,
    pub full_height: u32,
    pub region: Region,
    pub scene: u64,
    pub frame: u32,
    pub clock: f64,
    pub transfer: Transfer,
}

/// 64-bit FNV-1a: tiny, stable across platforms and Rust versions (the
/// standard library's hasher promises neither).
#[derive(Clone, Copy)]
struct Fnv(u64);

impl Fnv {
    fn new() -> Fnv {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
    fn bytes(mut self, bytes: &[u8]) -> Fnv {
        for &b in bytes {
            self.0 ^= b as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
        self
    }
    /// The bytes, then their length, so that ("ab", "c") ≠ ("a", "bc").
    fn field(self, bytes: &[u8]) -> Fnv {
        self.bytes(bytes).bytes(&(bytes.len() as u64).to_le_bytes())
    }
}

/// The identity of a scene and the settings that change its picture.
pub fn scene_identity(args: &Args, program: &crate::lang::Program) -> u64 {
    let mut h = Fnv::new();
    for i in 0..program.sources.len() {
        let file = program.sources.get(crate::lang::ast::FileId(i as u32));
        h = h.field(file.text.as_bytes());
    }
    for d in &args.defines {
        h = h.field(d.as_bytes());
    }
    for o in [args.width, args.height, args.samples] {
        h = h.field(o.map(|v| v.to_string()).unwrap_or_default().as_bytes());
    }
    h.0
}

fn transfer_word(t: Transfer) -> String {
    match t {
        Transfer::Srgb => "srgb".into(),
        Transfer::Linear => "linear".into(),
        Transfer::Gamma(g) => format!("gamma:{g:?}"),
    }
}

fn parse_transfer(s: &str) -> Option<Transfer> {
    match s {
        "srgb" => Some(Transfer::Srgb),
        "linear" => Some(Transfer::Linear),
        _ => s
            .strip_prefix("gamma:")?
            .parse()
            .ok()
            .filter(|g: &f64| *g > 0.0)
            .map(Transfer::Gamma),
    }
}

impl Stamp {
    /// The record of `region` of the picture `args` and `program` make.
    pub fn of(
        args: &Args,
        program: &crate::lang::Program,
        settings: &crate::scene::RenderSettings,
        region: Region,
    ) -> Stamp {
        Stamp {
            full_width: settings.width,
            full_height: settings.height,
            region,
            scene: scene_identity(args, program),
            frame: args.frame.unwrap_or(0),
            clock: args.clock,
            transfer: settings.transfer,
        }
    }

    pub fn is_full(&self) -> bool {
        self.region
            == Region {
                x: 0,
                y: 0,
                width: self.full_width,
                height: self.full_height,
            }
    }

    /// The record as one line of text.
    pub fn to_text(&self) -> String {
        let r = self.region;
        format!(
            "v=1 full={}x{} region={},{},{},{} scene={:016x} frame={} clock={:?} transfer={}",
            self.full_width,
            self.full_height,
            r.x,
            r.y,
            r.width,
            r.height,
            self.scene,
            self.frame,
            self.clock,
            transfer_word(self.transfer)
        )
    }

    /// Reads the record back; a message names the first part that is
    /// missing or malformed.
    pub fn parse(text: &str) -> Result<Stamp, String> {
        let mut map = std::collections::HashMap::new();
        for word in text.split_whitespace() {
            let (k, v) = word
                .split_once('=')
                .ok_or_else(|| format!("`{word}` is not key=value"))?;
            map.insert(k, v);
        }
        let get = |k: &str| map.get(k).copied().ok_or(format!("no `{k}`"));
        if get("v")? != "1" {
            return Err(format!("version {} (this program reads 1)", get("v")?));
        }
        let bad = |k: &str| format!("a malformed `{k}`");
        let (fw, fh) = get("full")?.split_once('x').ok_or_else(|| bad("full"))?;
        let full_width = fw.parse().map_err(|_| bad("full"))?;
        let full_height = fh.parse().map_err(|_| bad("full"))?;
        let r: Vec<u32> = get("region")?
            .split(',')
            .map(|t| t.parse().map_err(|_| bad("region")))
            .collect::<Result<_, _>>()?;
        let [x, y, width, height] = r[..] else {
            return Err(bad("region"));
        };
        let region = Region {
            x,
            y,
            width,
            height,
        };
        if width == 0
            || height == 0
            || x as u64 + width as u64 > full_width as u64
            || y as u64 + height as u64 > full_height as u64
        {
            return Err(format!(
                "a region {x},{y},{width},{height} outside the {fw}x{fh} picture"
            ));
        }
        Ok(Stamp {
            full_width,
            full_height,
            region,
            scene: u64::from_str_radix(get("scene")?, 16).map_err(|_| bad("scene"))?,
            frame: get("frame")?.parse().map_err(|_| bad("frame"))?,
            clock: get("clock")?.parse().map_err(|_| bad("clock"))?,
            transfer: parse_transfer(get("transfer")?).ok_or_else(|| bad("transfer"))?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stamp() -> Stamp {
        Stamp {
            full_width: 48,
            full_height: 32,
            region: Region {
                x: 24,
                y: 0,
                width: 24,
                height: 16,
            },
            scene: 0x9f0c_0000_0000_00e1,
            frame: 3,
            clock: 0.1 + 0.2,
            transfer: Transfer::Gamma(2.2),
        }
    }

    #[test]
    fn the_record_reads_back_exactly() {
        let s = stamp();
        let t = s.to_text();
        assert_eq!(Stamp::parse(&t).unwrap(), s, "{t}");
        for tr in [Transfer::Srgb, Transfer::Linear] {
            let s = Stamp {
                transfer: tr,
                ..s.clone()
            };
            assert_eq!(Stamp::parse(&s.to_text()).unwrap(), s);
        }
    }

    #[test]
    fn broken_records_say_what_is_wrong() {
        let t = stamp().to_text();
        let e = Stamp::parse(&t.replace("frame=3 ", "")).unwrap_err();
        assert!(e.contains("frame"), "{e}");
        let e = Stamp::parse(&t.replace("region=24,0,24,16", "region=40,0,24,16")).unwrap_err();
        assert!(e.contains("outside"), "{e}");
        let e = Stamp::parse(&t.replace("v=1", "v=2")).unwrap_err();
        assert!(e.contains("version"), "{e}");
    }

    #[test]
    fn the_hash_separates_fields() {
        let a = Fnv::new().field(b"ab").field(b"c").0;
        let b = Fnv::new().field(b"a").field(b"bc").0;
        assert_ne!(a, b);
        // The published FNV-1a test vectors: the identity must not change
        // between builds or machines.
        assert_eq!(Fnv::new().bytes(b"").0, 0xcbf2_9ce4_8422_2325);
        assert_eq!(Fnv::new().bytes(b"a").0, 0xaf63_dc4c_8601_ec8c);
        assert_eq!(Fnv::new().bytes(b"foobar").0, 0x8594_4171_f739_67e8);
    }
}
