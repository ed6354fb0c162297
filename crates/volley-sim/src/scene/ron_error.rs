//! The RON reader's errors in the scene file's own words.
//!
//! serde names the Rust types behind the format (`RawCurve`, `RawBody`), and lists an enum's
//! variants without their payloads. A user wrote `curve: G8` and should read "unknown drag
//! curve `G8`: expected one of G1, G7, Sphere, Table([(mach, cd), ...])". [`describe`] rewrites
//! the errors that name a type or list variants; every other message (a missing comma, an
//! unexpected character) names no type and is kept as the parser gives it.
//!
//! [`ENUMS`] is the one list of the format's enums: how the file calls each, and each variant as
//! a file writes it. A test parses a misspelt variant at every enum's place and checks the list
//! against serde's own, so a variant added to the format without a line here fails it.

/// One enum of the scene format: serde's name for it, what the file calls it, and its variants
/// as written in a file (payloads shown as a template).
pub(crate) struct EnumWords {
    /// The Rust type's name, as serde reports it.
    pub(crate) rust: &'static str,
    /// What a scene file calls it ("drag curve").
    pub(crate) words: &'static str,
    /// Every variant as a file writes it, in declaration order.
    pub(crate) variants: &'static [&'static str],
}

/// Every enum a scene file can name a variant of.
pub(crate) const ENUMS: &[EnumWords] = &[
    EnumWords {
        rust: "ForceTerm",
        words: "force term",
        variants: &[
            "Gravity((x, y, z))",
            "ConstantForce((x, y, z))",
            "LinearDrag(b)",
            "QuadraticDrag(c)",
            "Spring(anchor: (x, y, z), stiffness: k, ...)",
            "PointMass(center: (x, y, z), mu: mu)",
            "MachDrag(curve: ..., ...)",
            "Custom(name: \"...\", version: n)",
            "Thrust(curve: [(t, N), ...], ...)",
        ],
    },
    EnumWords {
        rust: "RawCurve",
        words: "drag curve",
        variants: &["G1", "G7", "Sphere", "Table([(mach, cd), ...])"],
    },
    EnumWords {
        rust: "RawAir",
        words: "air",
        variants: &[
            "Standard(ground: m, ...)",
            "Uniform(temperature: K, pressure: Pa)",
        ],
    },
    EnumWords {
        rust: "RawThrustDirection",
        words: "thrust direction",
        variants: &[
            "Fixed((x, y, z))",
            "Velocity(along: (x, y, z), rail_exit_speed: m/s)",
        ],
    },
    EnumWords {
        rust: "Launch",
        words: "launch",
        variants: &[
            "Velocity((x, y, z))",
            "Angles(speed: m/s, elevation_deg: deg, azimuth_deg: deg)",
            "Aim(target: (x, y, z), speed: m/s, arc: High or Low)",
        ],
    },
    EnumWords {
        rust: "Arc",
        words: "arc",
        variants: &["High", "Low"],
    },
    EnumWords {
        rust: "Integrator",
        words: "integrator",
        variants: &[
            "ExplicitEuler",
            "SemiImplicitEuler",
            "VelocityVerlet",
            "Midpoint",
            "Rk4",
            "ImplicitEuler",
            "Exact",
            "ForestRuth",
            "Dopri5",
            "ImplicitMidpoint",
        ],
    },
    EnumWords {
        rust: "Detection",
        words: "detection",
        variants: &["Swept", "Discrete"],
    },
    EnumWords {
        rust: "Interpolation",
        words: "interpolation",
        variants: &["Pchip", "Linear"],
    },
    EnumWords {
        rust: "LiftModel",
        words: "lift model",
        variants: &["Nathan"],
    },
    EnumWords {
        rust: "SpinDecay",
        words: "spin decay",
        variants: &["None", "Time(tau)", "Nathan(tau)"],
    },
    EnumWords {
        rust: "EventCondition",
        words: "event condition",
        variants: &[
            "Plane(point: (x, y, z), normal: (x, y, z))",
            "Altitude(z)",
            "Downrange(m)",
            "Speed(m/s)",
            "Mach(M)",
            "Apex",
            "Closest(point: (x, y, z), velocity: (x, y, z))",
            "ClosestToTarget(i)",
        ],
    },
    EnumWords {
        rust: "EventDirection",
        words: "event direction",
        variants: &["Rising", "Falling", "Either"],
    },
    EnumWords {
        rust: "EventStop",
        words: "event stop",
        variants: &["Never", "Body(n)", "Run(n)"],
    },
];

/// The format's structs (and struct-like variants) under serde's names, and what a file calls
/// them.
const STRUCTS: &[(&str, &str)] = &[
    ("RawScene", "the scene"),
    ("Scene", "the scene"),
    ("RawBody", "a body"),
    ("RawSpin", "a Mach drag's spin"),
    ("RawWind", "a Mach drag's wind"),
    ("Ground", "the ground"),
    ("Wall", "a wall"),
    ("Target", "a target"),
    ("Launcher", "the launcher"),
    ("Volley", "the volley"),
    ("Guard", "the guard"),
    ("CompareLane", "a compare lane"),
    ("RawEvent", "an event"),
];

/// What a file calls the type serde named `rust`: an enum's or struct's words, a struct-like
/// variant's own name (`Spring`, written as is), or the name itself if it is not ours.
fn words(rust: &str) -> String {
    if let Some(e) = ENUMS.iter().find(|e| e.rust == rust) {
        return e.words.to_string();
    }
    if let Some((_, w)) = STRUCTS.iter().find(|(r, _)| *r == rust) {
        return (*w).to_string();
    }
    format!("`{rust}`")
}

/// An enum's variants as a file writes them, found by serde's list of their names (serde does
/// not say which enum it was when it has no outer name).
fn variants_of(outer: Option<&str>, expected: &[&str]) -> Option<&'static EnumWords> {
    let named = |e: &&EnumWords| e.variants.len() == expected.len() && names_match(e, expected);
    match outer {
        Some(o) => ENUMS.iter().find(|e| e.rust == o),
        None => ENUMS.iter().find(named),
    }
}

fn names_match(e: &EnumWords, expected: &[&str]) -> bool {
    e.variants
        .iter()
        .zip(expected)
        .all(|(v, n)| variant_name(v) == *n)
}

/// A variant's name without its payload template.
pub(crate) fn variant_name(written: &str) -> &str {
    written.split('(').next().unwrap_or(written)
}

fn one_of(items: impl IntoIterator<Item = String>) -> String {
    let items: Vec<String> = items.into_iter().collect();
    match items.as_slice() {
        [] => "nothing here".to_string(),
        [one] => format!("expected {one}"),
        _ => format!("expected one of {}", items.join(", ")),
    }
}

/// The RON reader's error `code` in the scene file's words.
pub(crate) fn describe(code: &ron::Error) -> String {
    use ron::Error as E;
    match code {
        E::NoSuchEnumVariant {
            expected,
            found,
            outer,
        } => match variants_of(outer.as_deref(), expected) {
            Some(e) => format!(
                "unknown {} `{found}`: {}",
                e.words,
                one_of(e.variants.iter().map(|v| (*v).to_string()))
            ),
            None => format!(
                "unknown variant `{found}`: {}",
                one_of(expected.iter().map(|v| (*v).to_string()))
            ),
        },
        E::NoSuchStructField {
            expected,
            found,
            outer,
        } => format!(
            "unknown field `{found}`{}: {}",
            outer
                .as_deref()
                .map_or(String::new(), |o| format!(" in {}", words(o))),
            one_of(expected.iter().map(|v| (*v).to_string()))
        ),
        E::MissingStructField { field, outer } => format!(
            "missing field `{field}`{}",
            outer
                .as_deref()
                .map_or(String::new(), |o| format!(" in {}", words(o)))
        ),
        E::DuplicateStructField { field, outer } => format!(
            "field `{field}` given twice{}",
            outer
                .as_deref()
                .map_or(String::new(), |o| format!(" in {}", words(o)))
        ),
        E::ExpectedDifferentStructName { expected, found } => {
            format!(
                "expected {} (`{expected}(...)`), found `{found}`",
                words(expected)
            )
        }
        E::ExpectedNamedStructLike(name) if !name.is_empty() => {
            format!("expected `(` to open {}", words(name))
        }
        E::ExpectedStructName(name) => format!("expected the name `{name}` before `(`"),
        E::InvalidValueForType { expected, found } => {
            format!("expected {} but found {found}", plain(expected))
        }
        E::Message(text) => plain(text),
        other => other.to_string(),
    }
}

/// `text` with serde's type names (`struct RawBody`, `tuple variant RawCurve::Table`, `enum
/// Integrator`) put in the file's words.
fn plain(text: &str) -> String {
    let mut out = text.to_string();
    let names = ENUMS
        .iter()
        .map(|e| (e.rust, e.words))
        .chain(STRUCTS.iter().copied());
    for (rust, words) in names {
        for kind in [
            "struct variant",
            "tuple variant",
            "newtype variant",
            "unit variant",
        ] {
            out = out.replace(&format!("{kind} {rust}::"), &format!("{words} "));
        }
        for kind in ["struct", "enum"] {
            out = out.replace(&format!("{kind} {rust}"), words);
        }
    }
    out
}

#[cfg(test)]
mod tests;
