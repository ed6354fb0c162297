//! Rewrites one generated block of a file (BENCHMARKS.md): what the benches share.

use std::path::Path;

/// Replaces the block from the line `begin` to the line `end` in `path` with `block` (which
/// holds both lines), or appends it if the file has no such block, leaving every other section
/// of the file as it is.
pub fn splice(path: &Path, block: &str, begin: &str, end: &str) -> std::io::Result<()> {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let new = match (text.find(begin), text.find(end)) {
        (Some(b), Some(e)) if b < e => {
            let after = e + end.len();
            let rest = text[after..].strip_prefix('\n').unwrap_or(&text[after..]);
            format!("{}{block}{rest}", &text[..b])
        }
        _ => format!("{text}\n{block}"),
    };
    std::fs::write(path, new)
}
