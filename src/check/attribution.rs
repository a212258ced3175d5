//! Diagnostics about a template's body attributed to the instances they
//! come from (the last step of `check` for a file with templates).

use crate::diagnostic::Diagnostic;
use crate::span::Span;

/// Points the diagnostics about a template's body at the instances they come
/// from: one copy per distinct diagnostic, with a label at the instance (at
/// every instance of the template when the message names none).
pub(crate) fn attribute(
    list: Vec<Diagnostic>,
    instances: &[(Span, String, String, Span)],
) -> Vec<Diagnostic> {
    if instances.is_empty() {
        return list;
    }
    let mut out: Vec<Diagnostic> = Vec::new();
    for mut d in list {
        let key = |d: &Diagnostic| {
            (
                d.code,
                d.message.clone(),
                d.labels.iter().find(|l| l.primary).map(|l| l.span),
            )
        };
        if out.iter().any(|o| key(o) == key(&d)) {
            continue;
        }
        let Some(primary) = d.labels.iter().find(|l| l.primary).map(|l| l.span) else {
            out.push(d);
            continue;
        };
        let inside: Vec<&(Span, String, String, Span)> = instances
            .iter()
            .filter(|(t, ..)| {
                t.file == primary.file && t.start <= primary.start && primary.end <= t.end
            })
            .collect();
        if !inside.is_empty() {
            let text = format!(
                "{} {}",
                d.message,
                d.labels
                    .iter()
                    .map(|l| l.message.as_str())
                    .collect::<Vec<_>>()
                    .join(" ")
            );
            let named: Vec<_> = inside
                .iter()
                .filter(|(_, n, ..)| text.contains(&format!("`{n}.")))
                .copied()
                .collect();
            let which = if named.is_empty() { inside } else { named };
            for (_, name, template, at) in which {
                d = d.secondary(
                    *at,
                    format!("in instance `{name}` of template `{template}`"),
                );
            }
        }
        out.push(d);
    }
    out
}
