//! Wording of every checker diagnostic, written once. Codes: E01xx names,
//! E02xx units and values, E03xx geometry, E04xx elements, E05xx loads,
//! E06xx mobility; W for warnings.

use crate::diagnostic::Diagnostic;
use crate::span::Span;
use crate::units::Dim;

pub fn unknown_name<'a>(
    what: &str,
    name: &str,
    span: Span,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Diagnostic {
    Diagnostic::error("E0101", format!("unknown {what} `{name}`"))
        .primary(span, format!("no {what} is called `{name}`"))
        .did_you_mean(span, name, candidates)
}

pub fn duplicate(what: &str, name: &str, span: Span, first: Span) -> Diagnostic {
    Diagnostic::error("E0102", format!("{what} `{name}` is declared twice"))
        .primary(span, "declared again here")
        .secondary(first, "first declared here")
        .hint("names must be unique; rename one of them")
}

pub fn missing_ground(file_span: Span) -> Diagnostic {
    Diagnostic::error("E0103", "the model has no ground part")
        .primary(
            Span {
                end: file_span.start,
                ..file_span
            },
            "no `ground` in this file",
        )
        .hint("declare the fixed part with `ground chassis { ... }` instead of `part`")
}

pub fn second_ground(span: Span, first: Span) -> Diagnostic {
    Diagnostic::error("E0104", "the model has a second ground part")
        .primary(span, "a second `ground`")
        .secondary(first, "the ground is declared here")
        .hint("a model has exactly one ground; declare the others with `part`")
}

pub fn unknown_property<'a>(
    element: &str,
    key: &str,
    span: Span,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Diagnostic {
    let list: Vec<&str> = candidates.into_iter().collect();
    let d = Diagnostic::error("E0105", format!("a {element} has no property `{key}`"))
        .primary(span, "unknown property")
        .note(format!("{element} properties: {}", list.join(", ")));
    d.did_you_mean(span, key, list.iter().copied())
}

pub fn duplicate_property(key: &str, span: Span, first: Span) -> Diagnostic {
    Diagnostic::error("E0106", format!("property `{key}` is given twice"))
        .primary(span, "given again here")
        .secondary(first, "first given here")
}

pub fn missing_property(
    element: &str,
    name: &str,
    key: &str,
    span: Span,
    example: &str,
) -> Diagnostic {
    Diagnostic::error("E0107", format!("{element} `{name}` has no `{key}`"))
        .primary(span, format!("`{key}` missing here"))
        .hint(format!("add a line such as `{example}`"))
}

pub fn marker_on_other_part(part: &str, marker: &str, span: Span, owners: &[String]) -> Diagnostic {
    Diagnostic::error("E0108", format!("part `{part}` has no marker `{marker}`"))
        .primary(span, format!("`{marker}` is not a marker of `{part}`"))
        .hint(format!(
            "`{marker}` is a marker of {}",
            owners
                .iter()
                .map(|o| format!("`{o}`"))
                .collect::<Vec<_>>()
                .join(" and ")
        ))
}

pub fn wrong_dimension(expected: Dim, found: Dim, span: Span, example: &str) -> Diagnostic {
    let d = Diagnostic::error(
        "E0201",
        format!(
            "expected {}, found {}",
            expected.describe(),
            found.describe()
        ),
    )
    .primary(span, format!("this is {}", found.describe()));
    if found == Dim::NONE {
        d.hint(format!("write the unit after the number, e.g. `{example}`"))
    } else {
        d.hint(format!("a value here is written like `{example}`"))
    }
}

pub fn unknown_unit(text: &str, piece: &str, span: Span) -> Diagnostic {
    let names = crate::units::UNIT_NAMES.iter().map(|(n, _)| *n);
    let d = Diagnostic::error("E0202", format!("unknown unit `{piece}` in `{text}`"))
        .primary(span, "not a unit");
    match crate::diagnostic::suggest::best(piece, names) {
        Some(c) => {
            let d = d.hint(crate::diagnostic::suggest::did_you_mean_text(c));
            // The unit with the one misspelt factor replaced: `N/mn` → `N/mm`.
            let factors: Vec<&str> = text.split(['*', '/']).collect();
            let replaced = factors
                .iter()
                .position(|f| f.split('^').next() == Some(piece));
            match replaced {
                Some(_) => d.fix(span, text.replacen(piece, c, 1)),
                None => d,
            }
        }
        None => d.hint(
            "units: mm, cm, m, N, kN, deg, rad, kg, s, combined as `N/mm`, `N*mm/deg`, `N/mm^3`",
        ),
    }
}

pub fn wrong_value_kind(expected: &str, found: &str, span: Span, example: &str) -> Diagnostic {
    Diagnostic::error("E0203", format!("expected {expected}, found {found}"))
        .primary(span, format!("this is {found}"))
        .hint(format!("write it like `{example}`"))
}

pub fn bad_number(what: &str, span: Span, why: &str) -> Diagnostic {
    Diagnostic::error("E0204", format!("{what} {why}")).primary(span, why.to_string())
}

/// Magnitudes (internal units) no suspension comes near: a value beyond them
/// is a slip of unit or exponent (`305 m` for `305 mm`, `1e200 N`), and would
/// swamp every tolerance of the solver.
pub const PLAUSIBLE: &[(Dim, f64, &str)] = &[
    (Dim::LENGTH, 1e5, "100 m"),
    (Dim::FORCE, 1e7, "10 MN"),
    (Dim::TORQUE, 1e10, "10 MN*m"),
    (Dim::STIFFNESS, 1e12, "1e12 N/mm"),
    (Dim::ROT_STIFFNESS, 1e15, "1e15 N*mm/rad"),
];

/// E0214 when `value` of dimension `dim` is beyond [`PLAUSIBLE`].
pub fn beyond_any_suspension(value: f64, dim: Dim, span: Span) -> Option<Diagnostic> {
    let (_, limit, shown) = PLAUSIBLE.iter().find(|(d, ..)| *d == dim)?;
    (value.abs() > *limit).then(|| {
        let (f, u) = (dim.boundary_factor(), dim.boundary_unit());
        Diagnostic::error(
            "E0214",
            format!(
                "{:e} {u} is beyond any suspension (more than {shown})",
                value / f
            ),
        )
        .primary(span, "this value")
        .hint("check the unit and the exponent")
    })
}

pub fn negative_stiffness(element: &str, what: &str, span: Span) -> Diagnostic {
    Diagnostic::error("E0205", format!("negative stiffness in {element}"))
        .primary(span, format!("{what} is negative"))
        .hint("a stiffness is zero or positive; flip the sign or check the unit")
}

pub fn length_not_positive(element: &str, key: &str, span: Span) -> Diagnostic {
    Diagnostic::error("E0212", format!("`{key}` of {element} must be positive"))
        .primary(span, "a length between two points is positive")
        .hint("check the sign and the unit (`290 mm`)")
}

pub fn stop_table_start(span: Span, why: &str) -> Diagnostic {
    Diagnostic::error("E0213", "a stop's table must start at first contact")
        .primary(span, why.to_string())
        .hint("write the force of the penetration from contact on: `law table (mm, N) [(0, 0), (10, 500), (20, 2000)]`")
}

pub fn table_too_short(span: Span, n: usize) -> Diagnostic {
    Diagnostic::error(
        "E0206",
        format!("a table needs at least 2 points, this one has {n}"),
    )
    .primary(span, "too few points")
}

pub fn table_not_increasing(span: Span, prev: Span) -> Diagnostic {
    Diagnostic::error("E0207", "table abscissae must increase strictly")
        .primary(span, "not larger than the previous point")
        .secondary(prev, "previous point")
}

pub fn table_not_monotone(span: Span, prev: Span, direction: &str) -> Diagnostic {
    Diagnostic::error(
        "E0208",
        format!("the table's force must {direction} with its abscissa"),
    )
    .primary(span, "the force turns back here")
    .secondary(prev, "previous point")
    .hint("a non-monotone law has several equilibria for one load; check the signs")
}

pub fn degenerate_direction(what: &str, span: Span) -> Diagnostic {
    Diagnostic::error("E0301", format!("degenerate orientation: {what}"))
        .primary(span, what.to_string())
        .hint("give a non-zero z direction and an x hint that is not parallel to it")
}

pub fn same_part(element: &str, name: &str, part: &str, i: Span, j: Span) -> Diagnostic {
    Diagnostic::error(
        "E0302",
        format!("both markers of {element} `{name}` are on part `{part}`"),
    )
    .primary(j, format!("J is on `{part}`"))
    .secondary(i, format!("I is on `{part}` too"))
    .hint("a connection joins two different parts")
}

pub fn unknown_module<'a>(
    name: &str,
    span: Span,
    modules: impl IntoIterator<Item = &'a str>,
) -> Diagnostic {
    let list: Vec<&str> = modules.into_iter().collect();
    let d = Diagnostic::error("E0109", format!("unknown module `{name}`"))
        .primary(span, "not a stdlib module")
        .note(format!("stdlib modules: {}", list.join(", ")));
    d.did_you_mean(span, name, list.iter().copied())
}

pub fn friction_without_axis(
    name: &str,
    joint: &str,
    kind: &str,
    motion: &str,
    at: Span,
    decl: Option<Span>,
) -> Diagnostic {
    let allowed = match motion {
        "slide" => "a cylindrical or translational joint",
        _ => "a revolute, cylindrical or spherical joint",
    };
    let d = Diagnostic::error(
        "E0412",
        format!("friction `{name}` needs a {motion} axis, and {kind} joint `{joint}` has none"),
    )
    .primary(at, format!("a {kind} joint has no {motion} axis"))
    .hint(format!(
        "a {motion} friction acts on {allowed} (the z axis of its J marker)"
    ));
    match decl {
        Some(s) => d.secondary(s, format!("`{joint}` is declared {kind} here")),
        None => d,
    }
}

pub fn friction_stiffness_not_positive(name: &str, span: Span) -> Diagnostic {
    Diagnostic::error(
        "E0413",
        format!("the stick stiffness `kf` of friction `{name}` must be positive"),
    )
    .primary(span, "zero or negative")
    .hint("kf is the stiffness before the slider slips, e.g. `kf 1000 N/mm`")
}

pub fn friction_limit_negative(name: &str, span: Span) -> Diagnostic {
    Diagnostic::error(
        "E0414",
        format!("the slip limit of friction `{name}` is negative"),
    )
    .primary(span, "negative")
    .hint("the Coulomb limit is a magnitude, zero or positive, e.g. `limit 150 N`")
}
