//! docs/cli.md is the manual of the command line: every subcommand, every option each one's
//! `--help` lists, and every integrator name the options take are in it. (Checked by hand:
//! deleting `forest-ruth` or `--frame-every` from the page fails these tests, naming it.)

use std::process::Command;

fn page() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/cli.md")).unwrap()
}

/// Whether `word` is on the page with no letter, digit, `-` or `_` touching it.
fn on_page(page: &str, word: &str) -> bool {
    let is_word = |c: char| c.is_ascii_alphanumeric() || c == '-' || c == '_';
    page.match_indices(word).any(|(i, _)| {
        page[..i].chars().next_back().is_none_or(|c| !is_word(c))
            && page[i + word.len()..]
                .chars()
                .next()
                .is_none_or(|c| !is_word(c))
    })
}

fn help(sub: &str) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_volley"))
        .args([sub, "--help"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{sub} --help");
    String::from_utf8(out.stdout).unwrap()
}

const SUBCOMMANDS: [&str; 9] = [
    "headless", "aim", "scenes", "study", "pacing", "record", "replay", "synctest", "window",
];

#[test]
fn the_manual_names_every_subcommand_and_every_option_of_each() {
    let page = page();
    let mut missing = Vec::new();
    for sub in SUBCOMMANDS {
        if !on_page(&page, &format!("volley {sub}")) {
            missing.push(format!("volley {sub}"));
        }
        let text = help(sub);
        let mut options: Vec<&str> = text
            .split(|c: char| !(c.is_ascii_alphanumeric() || c == '-'))
            .filter(|w| w.starts_with("--") && w.len() > 2)
            .collect();
        options.sort_unstable();
        options.dedup();
        assert!(!options.is_empty() || sub == "scenes", "{sub}: {text}");
        missing.extend(
            options
                .into_iter()
                .filter(|o| *o != "--help" && !on_page(&page, o))
                .map(|o| format!("{sub} {o}")),
        );
    }
    assert!(missing.is_empty(), "docs/cli.md never names {missing:?}");
}

#[test]
fn the_manual_names_every_integrator_the_options_take() {
    let (page, text) = (page(), help("headless"));
    for integrator in volley::Integrator::ALL {
        let name = integrator.name();
        assert!(text.contains(name), "`volley headless --help` lists {name}");
        assert!(on_page(&page, name), "docs/cli.md never names {name}");
    }
}
