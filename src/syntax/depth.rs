//! A bound on how deep an expression can nest, checked on the raw text before
//! pest sees it: the parser, the syntax tree and every pass over it recurse
//! once per parenthesis and once per operator, so 1600 nested parentheses or
//! 100 000 unary minus signs would overflow the stack. No suspension model
//! comes near the bounds; a file beyond them gets E0005 at the character
//! that crosses them. These bounds are the parser's only guard: pest is built
//! without its per-rule stack probe (Cargo.toml), which cost a tenth of a
//! short command.

use crate::diagnostic::Diagnostic;
use crate::span::{FileId, Span};

/// Parentheses open at once.
pub const MAX_PARENS: usize = 48;
/// Nesting of one expression: open parentheses plus the operators along the
/// way (each `+ - * /` makes the tree one level deeper).
pub const MAX_DEPTH: usize = 256;

/// E0005 at the first character where an expression nests too deeply.
pub fn check(file: FileId, text: &str) -> Result<(), Diagnostic> {
    // Operators counted at each open parenthesis level; their sum is the
    // depth of the tree at this point. `,` and a line end at level 0 start
    // a new expression at their level.
    let mut levels: Vec<usize> = vec![0];
    let mut depth = 0usize;
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                while i < bytes.len() && bytes[i] != b'\n' && bytes[i] != b'\r' {
                    i += 1;
                }
                continue;
            }
            b'(' => {
                levels.push(1);
                depth += 1;
                if levels.len() - 1 > MAX_PARENS {
                    return Err(too_deep(
                        file,
                        i,
                        "parentheses nested more than",
                        MAX_PARENS,
                    ));
                }
            }
            b')' if levels.len() > 1 => depth -= levels.pop().unwrap_or(0),
            b',' => {
                // The level's own parenthesis stays counted.
                let keep = usize::from(levels.len() > 1);
                if let Some(top) = levels.last_mut() {
                    depth -= *top - keep;
                    *top = keep;
                }
            }
            b'\n' | b'\r' if levels.len() == 1 => {
                levels[0] = 0;
                depth = 0;
            }
            b'+' | b'-' | b'*' | b'/' => {
                if let Some(top) = levels.last_mut() {
                    *top += 1;
                }
                depth += 1;
            }
            _ => {}
        }
        if depth > MAX_DEPTH {
            return Err(too_deep(
                file,
                i,
                "an expression nested more than",
                MAX_DEPTH,
            ));
        }
        i += 1;
    }
    Ok(())
}

fn too_deep(file: FileId, at: usize, what: &str, limit: usize) -> Diagnostic {
    Diagnostic::error("E0005", format!("{what} {limit} levels deep"))
        .primary(Span::new(file, at, at + 1), "nested too deeply here")
        .hint("write the value as a number, or split it with `param` lines")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn depth_error(text: &str) -> Option<usize> {
        check(FileId(0), text)
            .err()
            .map(|d| d.labels[0].span.start as usize)
    }

    #[test]
    fn realistic_expressions_pass_and_the_bounds_are_exact() {
        assert_eq!(
            depth_error("k (310, 2400 - 2 * 3, -(180)) N/mm // a - b\n"),
            None
        );
        let at_limit = format!("{}1{}", "(".repeat(MAX_PARENS), ")".repeat(MAX_PARENS));
        assert_eq!(depth_error(&at_limit), None);
        let over = format!(
            "{}1{}",
            "(".repeat(MAX_PARENS + 1),
            ")".repeat(MAX_PARENS + 1)
        );
        assert_eq!(depth_error(&over), Some(MAX_PARENS));
        let minus = format!("x {}1\n", "-".repeat(MAX_DEPTH));
        assert_eq!(depth_error(&minus), None);
        assert_eq!(
            depth_error(&format!("x -{}", &minus[2..])),
            Some(2 + MAX_DEPTH)
        );
        // Commas and line ends start new expressions: a long table is fine.
        let table = "a -1 -2 -3 -4\n".repeat(10_000);
        assert_eq!(depth_error(&table), None);
        let vector = format!("({})", vec!["-1"; 10_000].join(", "));
        assert_eq!(depth_error(&vector), None);
    }

    /// pest is built without its per-rule stack probe (Cargo.toml): these
    /// bounds are what keep its recursion, and the syntax tree's, finite.
    /// The deepest file they let through (every parenthesis open at once,
    /// each level holding an operator chain up to the depth bound) parses
    /// and checks on a thread of 512 KiB of stack, a quarter of a spawned
    /// thread's default (the language server's, rayon's, a test's) and a
    /// sixteenth of the main thread's. Measured: the release build needs
    /// between 256 and 384 KiB for it, the test profile between 128 and
    /// 192 KiB (its frames are smaller: less is inlined).
    #[test]
    fn the_deepest_file_the_bounds_allow_parses_on_a_small_stack() {
        // The vector's parenthesis is one level; each level inside adds a
        // parenthesis and a `*` to its operators.
        let levels = MAX_PARENS - 1;
        let per_level = (MAX_DEPTH - 1 - 2 * levels) / (levels + 1);
        let chain = |k: usize| vec!["1"; k + 1].join(" - ");
        let mut value = chain(per_level);
        for _ in 0..levels {
            value = format!("{} * ({value})", chain(per_level));
        }
        let src = format!("ground g {{\n    marker o at ({value}, 0, 0) mm\n}}\n");
        assert_eq!(check(FileId(0), &src).map_err(|d| d.message), Ok(()));
        // At the bounds: one more level is refused.
        let deeper = src
            .replacen("at (", "at ((", 1)
            .replacen(", 0, 0)", "), 0, 0)", 1);
        assert!(check(FileId(0), &deeper).is_err());
        let parsed = std::thread::Builder::new()
            .stack_size(512 * 1024)
            .spawn(move || {
                let (_, checked) = crate::check::check_str("deep.axle", &src);
                checked
                    .problems
                    .list
                    .iter()
                    .map(|d| d.code)
                    .collect::<Vec<_>>()
            })
            .map(|t| t.join());
        assert!(
            matches!(parsed, Ok(Ok(ref codes)) if codes.is_empty()),
            "{parsed:?}"
        );
    }
}
