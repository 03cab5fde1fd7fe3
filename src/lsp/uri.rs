//! File paths ↔ `file://` URIs, percent-encoded as editors send them
//! (`/a b/é.rt` ↔ `file:///a%20b/%C3%A9.rt`).

use lsp_types::Uri;
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// The path a `file:` URI names; `None` for other schemes.
pub fn to_path(uri: &Uri) -> Option<PathBuf> {
    let s = uri.as_str();
    let rest = s.strip_prefix("file://")?;
    // `file://host/path`: only the local host (empty or `localhost`).
    let rest = rest.strip_prefix("localhost").unwrap_or(rest);
    if !rest.starts_with('/') {
        return None;
    }
    let bytes = decode(rest)?;
    Some(PathBuf::from(String::from_utf8(bytes).ok()?))
}

/// The `file:` URI of a path (made absolute against the working folder).
pub fn from_path(path: &Path) -> Option<Uri> {
    let abs = if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir().ok()?.join(path)
    };
    let mut s = String::from("file://");
    for b in abs.to_str()?.bytes() {
        if b.is_ascii_alphanumeric() || b"/-._~".contains(&b) {
            s.push(b as char);
        } else {
            s.push_str(&format!("%{b:02X}"));
        }
    }
    Uri::from_str(&s).ok()
}

fn decode(s: &str) -> Option<Vec<u8>> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = std::str::from_utf8(b.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_round_trip_with_spaces_and_accents() {
        let p = Path::new("/tmp/a b/é#1.rt");
        let u = from_path(p).unwrap();
        assert_eq!(u.as_str(), "file:///tmp/a%20b/%C3%A9%231.rt");
        assert_eq!(to_path(&u).unwrap(), p);
    }

    #[test]
    fn other_schemes_are_no_files() {
        let u = Uri::from_str("untitled:Untitled-1").unwrap();
        assert!(to_path(&u).is_none());
        let u = Uri::from_str("file://localhost/x.rt").unwrap();
        assert_eq!(to_path(&u).unwrap(), Path::new("/x.rt"));
    }
}
