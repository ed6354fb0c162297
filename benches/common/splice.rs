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

/// With `VOLLEY_BENCH_WRITE=FILE`, replaces the block of `md` (from `begin` to `end`) in FILE,
/// saying so on stderr; without it, nothing. What every bench that writes BENCHMARKS.md ends
/// with.
pub fn write_if_asked(md: &str, begin: &str, end: &str) {
    if let Some(path) = std::env::var_os("VOLLEY_BENCH_WRITE") {
        let path = std::path::PathBuf::from(path);
        match splice(&path, md, begin, end) {
            Ok(()) => eprintln!("wrote the results into {}", path.display()),
            Err(e) => eprintln!("cannot update {}: {e}", path.display()),
        }
    }
}
