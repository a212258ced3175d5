//! Templates and instances → the flat list of items every later pass reads
//! (the first step of `check`). Every name an instance declares becomes
//! `INSTANCE.name` (`front_left.upright`, `front_left.B`); a reference inside a
//! template resolves to the instance's own names first, then to the top-level
//! ones. Template parameters are replaced by the instance's argument (or the
//! default) in brackets. Mirroring is not done here: the names of the
//! mirrored parts and ground markers are recorded and `Checker::mirror`
//! reflects their checked frames.

use super::instance_scope::{Scope, rewrite_expr, rewrite_part_item, rewrite_value};
use crate::diagnostic::Diagnostic;
use crate::span::Span;
use crate::syntax::ast::*;
use std::collections::{BTreeMap, BTreeSet};

/// Instances nested deeper than this are reported as recursive.
const MAX_DEPTH: usize = 16;

/// The expanded file and what the checker needs to know about its instances.
#[derive(Debug, Default)]
pub(crate) struct Expansion {
    /// Items without templates or instances.
    pub items: Vec<Item>,
    /// Parts (expanded names) of mirrored instances.
    pub mirrored_parts: BTreeSet<String>,
    /// `(ground, marker)` of the ground markers mirrored instances add.
    pub mirrored_markers: BTreeSet<(String, String)>,
    /// For every expanded instance: the span of its template's item, its
    /// expanded name, its template's name and the instance line.
    pub instances: Vec<(Span, String, String, Span)>,
    pub problems: Vec<Diagnostic>,
}

/// Expands every instance of the file; `imported` holds the template items
/// of the modules the file imports.
pub(crate) fn expand(file: &File, imported: &[Item]) -> Expansion {
    let mut templates: BTreeMap<&str, (&TemplateDecl, Span)> = BTreeMap::new();
    let mut x = Expansion::default();
    for item in imported.iter().chain(&file.items) {
        if let ItemKind::Template(t) = &item.kind {
            if let Some((first, _)) = templates.get(t.name.name.as_str()) {
                x.problems.push(super::error::duplicate(
                    "template",
                    &t.name.name,
                    t.name.span,
                    first.name.span,
                ));
                continue;
            }
            templates.insert(&t.name.name, (t, item.span));
        }
    }
    if templates.is_empty()
        && !file
            .items
            .iter()
            .any(|i| matches!(i.kind, ItemKind::Instance(_)))
    {
        x.items = file.items.clone();
        return x;
    }
    // Top-level names an instance may not take (its expanded names would read
    // like a marker of that part: `front_left.upright`).
    let mut top: BTreeMap<&str, Span> = BTreeMap::new();
    let mut ground = None;
    for item in &file.items {
        let name = match &item.kind {
            ItemKind::Param(p) => &p.name,
            ItemKind::Part(p) => {
                if p.ground && ground.is_none() {
                    ground = Some(p.name.name.clone());
                }
                &p.name
            }
            ItemKind::Element(e) => &e.name,
            ItemKind::Loads(l) => &l.name,
            ItemKind::Template(t) => &t.name,
            _ => continue,
        };
        top.entry(&name.name).or_insert(name.span);
    }
    let mut ex = Expander {
        templates,
        ground,
        out: &mut x,
        extensions: Vec::new(),
        seen: BTreeMap::new(),
    };
    let mut items = Vec::new();
    for item in &file.items {
        match &item.kind {
            ItemKind::Template(_) => {}
            ItemKind::Instance(i) => {
                if let Some(first) = top.get(i.name.name.as_str()) {
                    ex.out.problems.push(
                        Diagnostic::error(
                            "E0115",
                            format!(
                                "instance `{}` has the name of a top-level item",
                                i.name.name
                            ),
                        )
                        .primary(i.name.span, "instance named here")
                        .secondary(*first, "the top-level item with this name")
                        .note(format!(
                            "the instance's names would read `{}.NAME`, like a marker of that item",
                            i.name.name
                        ))
                        .hint("rename the instance or the item"),
                    );
                    continue;
                }
                ex.instance(i, item.span, "", false, &[], &Scope::default(), &mut items);
            }
            _ => items.push(item.clone()),
        }
    }
    // Markers instances add to a part outside them (the ground, a rack
    // passed as a part parameter) go at the end of that part's block.
    let extensions = std::mem::take(&mut ex.extensions);
    let mut missing = BTreeSet::new();
    for e in extensions {
        let target = items.iter_mut().find_map(|i| match &mut i.kind {
            ItemKind::Part(p) if p.name.name == e.target => Some(p),
            _ => None,
        });
        match (target, e.origin) {
            (Some(p), _) => p.items.push(e.item),
            (None, Some((block, arg, template))) => {
                if missing.insert((e.target.clone(), arg)) {
                    x.problems.push(
                        Diagnostic::error(
                            "E0116",
                            format!(
                                "template `{template}` adds markers to part `{}`, which the model does not have",
                                e.target
                            ),
                        )
                        .primary(arg, "no part of this name")
                        .secondary(block, "the markers are added here")
                        .hint("a part parameter takes the name of a part of the model: a top-level part, the ground, or an instance's part (`steering.rack`)"),
                    );
                }
            }
            // The ground's absence is reported where the block is expanded.
            (None, None) => {}
        }
    }
    x.items = items;
    x
}

/// Markers an instance adds to a part outside it, kept until every part of
/// the file is expanded: the target part, the marker, and for a part
/// parameter the block's and the argument's spans and the template, to
/// report a target that does not exist.
struct Extension {
    target: String,
    item: PartItem,
    origin: Option<(Span, Span, String)>,
}

struct Expander<'a> {
    templates: BTreeMap<&'a str, (&'a TemplateDecl, Span)>,
    ground: Option<String>,
    out: &'a mut Expansion,
    /// Markers and landmarks instances add to parts outside them.
    extensions: Vec<Extension>,
    /// Expanded instance names → their name's span, for duplicates.
    seen: BTreeMap<String, Span>,
}

impl Expander<'_> {
    /// Expands `i` (declared in `outer`'s scope) under `prefix`.
    #[allow(clippy::too_many_arguments)]
    fn instance(
        &mut self,
        i: &InstanceDecl,
        span: Span,
        prefix: &str,
        mirrored: bool,
        stack: &[(String, Span)],
        outer: &Scope,
        items: &mut Vec<Item>,
    ) {
        let full = format!("{prefix}{}", i.name.name);
        if let Some(first) = self.seen.get(&full) {
            self.out.problems.push(super::error::duplicate(
                "instance",
                &full,
                i.name.span,
                *first,
            ));
            return;
        }
        self.seen.insert(full.clone(), i.name.span);
        let Some(&(t, t_span)) = self.templates.get(i.template.name.as_str()) else {
            let names: Vec<&str> = self.templates.keys().copied().collect();
            self.out.problems.push(
                super::error::unknown_name("template", &i.template.name, i.template.span, names)
                    .note("templates are declared with `template NAME(params) { ... }`"),
            );
            return;
        };
        if stack.iter().any(|(n, _)| n == &t.name.name) || stack.len() > MAX_DEPTH {
            let chain: Vec<&str> = stack
                .iter()
                .map(|(n, _)| n.as_str())
                .chain([t.name.name.as_str()])
                .collect();
            let mut d = Diagnostic::error(
                "E0112",
                format!("template `{}` instances itself", t.name.name),
            )
            .primary(i.template.span, "instanced again here")
            .note(format!("the chain of instances: {}", chain.join(" -> ")))
            .hint("a template cannot contain an instance of itself, directly or through another template");
            if let Some((_, first)) = stack.first() {
                d = d.secondary(*first, "the outermost instance");
            }
            self.out.problems.push(d);
            return;
        }
        // Arguments.
        let mut args: BTreeMap<String, Expr> = BTreeMap::new();
        let mut raw: BTreeMap<&str, &Expr> = BTreeMap::new();
        let mut ok = true;
        for a in &i.args {
            if !t.params.iter().any(|p| p.name.name == a.name.name) {
                let names: Vec<&str> = t.params.iter().map(|p| p.name.name.as_str()).collect();
                self.out.problems.push(
                    Diagnostic::error(
                        "E0114",
                        format!(
                            "template `{}` has no parameter `{}`",
                            t.name.name, a.name.name
                        ),
                    )
                    .primary(a.name.span, "no such parameter")
                    .secondary(t.params_span, "the template's parameters")
                    .did_you_mean(a.name.span, &a.name.name, names),
                );
                ok = false;
                continue;
            }
            if args.contains_key(&a.name.name) {
                self.out.problems.push(
                    Diagnostic::error(
                        "E0114",
                        format!("argument `{}` is given twice", a.name.name),
                    )
                    .primary(a.span, "given again here")
                    .secondary(t.params_span, "the template's parameters"),
                );
                ok = false;
                continue;
            }
            args.insert(a.name.name.clone(), rewrite_expr(&a.value, outer));
            raw.insert(&a.name.name, &a.value);
        }
        for p in &t.params {
            if args.contains_key(&p.name.name) {
                continue;
            }
            match &p.default {
                Some(d) => {
                    args.insert(p.name.name.clone(), rewrite_expr(d, &Scope::default()));
                    raw.insert(&p.name.name, d);
                }
                None => {
                    self.out.problems.push(
                        Diagnostic::error(
                            "E0113",
                            format!(
                                "instance `{full}` does not give parameter `{}` of template `{}`",
                                p.name.name, t.name.name
                            ),
                        )
                        .primary(i.args_span, format!("`{}` missing here", p.name.name))
                        .secondary(p.span, "a parameter without a default")
                        .hint(format!("add `{} = VALUE` to the arguments", p.name.name)),
                    );
                    ok = false;
                }
            }
        }
        // Part parameters: a parameter the body uses as a part (a `part P {
        // ... }` block adding markers to it, or a reference `P.marker`) takes
        // a part's name, resolved where the instance is written.
        let mut part_args: BTreeMap<String, String> = BTreeMap::new();
        for p in t.params.iter().filter(|p| is_part_param(t, &p.name.name)) {
            let Some(e) = raw.get(p.name.name.as_str()) else {
                continue;
            };
            let ExprKind::Param(id) = &e.kind else {
                self.out.problems.push(
                    Diagnostic::error(
                        "E0118",
                        format!(
                            "parameter `{}` of template `{}` is a part: its argument must be a part's name",
                            p.name.name, t.name.name
                        ),
                    )
                    .primary(e.span, "not a part's name")
                    .secondary(p.span, "used as a part in the template")
                    .hint("pass the name of a part: `rack = steering.rack`, or `rack = chassis` for the ground"),
                );
                ok = false;
                continue;
            };
            let target = match outer.parts.get(&id.name) {
                Some(own) => own.clone(),
                None => match outer.extends.get(&id.name) {
                    Some((target, _)) => target.clone(),
                    None => id.name.clone(),
                },
            };
            args.remove(&p.name.name);
            part_args.insert(p.name.name.clone(), target);
        }
        let arg_span = |name: &str| raw.get(name).map(|e| e.span).unwrap_or(i.args_span);
        if !ok {
            return;
        }
        self.out
            .instances
            .push((t_span, full.clone(), t.name.name.clone(), span));
        let mirrored = mirrored ^ i.mirror;
        // The instance's own names.
        let mut scope = Scope {
            args: args
                .into_iter()
                .map(|(n, e)| {
                    let span = e.span;
                    let paren = Expr {
                        kind: ExprKind::Paren(Box::new(e)),
                        span,
                    };
                    (n, paren)
                })
                .collect(),
            ..Scope::default()
        };
        for item in &t.items {
            let q = |n: &Ident| (n.name.clone(), format!("{full}.{}", n.name));
            match &item.kind {
                ItemKind::Part(p) if p.ground || part_args.contains_key(&p.name.name) => {
                    let target = part_args
                        .get(&p.name.name)
                        .cloned()
                        .unwrap_or_else(|| p.name.name.clone());
                    let entry = scope
                        .extends
                        .entry(p.name.name.clone())
                        .or_insert_with(|| (target, BTreeMap::new()));
                    entry.1.extend(p.items.iter().map(|pi| q(pi.name())));
                }
                ItemKind::Part(p) => scope.parts.extend([q(&p.name)]),
                ItemKind::Param(p) => scope.names.extend([q(&p.name)]),
                ItemKind::Element(e) => scope.names.extend([q(&e.name)]),
                _ => {}
            }
        }
        for (local, target) in &part_args {
            scope
                .extends
                .entry(local.clone())
                .or_insert_with(|| (target.clone(), BTreeMap::new()));
        }
        let mut stack = stack.to_vec();
        stack.push((t.name.name.clone(), i.template.span));
        for item in &t.items {
            let renamed = |n: &Ident, map: &BTreeMap<String, String>| Ident {
                name: map.get(&n.name).cloned().unwrap_or_else(|| n.name.clone()),
                span: n.span,
            };
            match &item.kind {
                ItemKind::Part(p) if p.ground => {
                    let Some(g) = self.ground.clone().filter(|g| *g == p.name.name) else {
                        self.out.problems.push(
                            Diagnostic::error(
                                "E0116",
                                format!(
                                    "template `{}` adds markers to ground `{}`, which the model does not have",
                                    t.name.name, p.name.name
                                ),
                            )
                            .primary(p.name.span, "not the model's ground")
                            .hint(match &self.ground {
                                Some(g) => format!("the model's ground is `{g}`"),
                                None => "declare the ground (`ground chassis { ... }`) outside the template".into(),
                            }),
                        );
                        continue;
                    };
                    self.extend(&g, p, &scope, &full, mirrored, None);
                }
                ItemKind::Part(p) if part_args.contains_key(&p.name.name) => {
                    let origin = (p.name.span, arg_span(&p.name.name), t.name.name.clone());
                    let target = &part_args[&p.name.name];
                    self.extend(target, p, &scope, &full, mirrored, Some(origin));
                }
                ItemKind::Part(p) => {
                    let name = renamed(&p.name, &scope.parts);
                    if mirrored {
                        self.out.mirrored_parts.insert(name.name.clone());
                    }
                    let decl = PartDecl {
                        ground: false,
                        keyword_span: p.keyword_span,
                        name,
                        items: p
                            .items
                            .iter()
                            .map(|pi| rewrite_part_item(pi, &scope, ""))
                            .collect(),
                    };
                    items.push(Item {
                        kind: ItemKind::Part(decl),
                        span: item.span,
                    });
                }
                ItemKind::Param(p) => {
                    let decl = ParamDecl {
                        name: renamed(&p.name, &scope.names),
                        value: rewrite_expr(&p.value, &scope),
                        unknown: p.unknown.as_ref().map(|u| Unknown {
                            bounds: u.bounds.as_ref().map(|(lo, hi)| {
                                (
                                    lo.as_ref().map(|e| rewrite_expr(e, &scope)),
                                    hi.as_ref().map(|e| rewrite_expr(e, &scope)),
                                )
                            }),
                            span: u.span,
                        }),
                    };
                    items.push(Item {
                        kind: ItemKind::Param(decl),
                        span: item.span,
                    });
                }
                ItemKind::Element(e) => {
                    let decl = ElementDecl {
                        keyword: e.keyword,
                        name: renamed(&e.name, &scope.names),
                        kind: e.kind.clone(),
                        props: e
                            .props
                            .iter()
                            .map(|p| Property {
                                key: p.key.clone(),
                                value: rewrite_value(&p.value, &scope),
                                span: p.span,
                            })
                            .collect(),
                    };
                    items.push(Item {
                        kind: ItemKind::Element(decl),
                        span: item.span,
                    });
                }
                ItemKind::Instance(inner) => {
                    let prefix = format!("{full}.");
                    self.instance(inner, item.span, &prefix, mirrored, &stack, &scope, items);
                }
                // The grammar admits nothing else in a template.
                _ => {}
            }
        }
    }
}

impl Expander<'_> {
    /// Records the markers of an instance's block `p` (a `ground` block or
    /// a part parameter's) for the part `target` outside it, mirrored with
    /// the instance.
    fn extend(
        &mut self,
        target: &str,
        p: &PartDecl,
        scope: &Scope,
        full: &str,
        mirrored: bool,
        origin: Option<(Span, Span, String)>,
    ) {
        for pi in &p.items {
            let pi = rewrite_part_item(pi, scope, full);
            if mirrored {
                let name = pi.name().name.clone();
                self.out.mirrored_markers.insert((target.to_string(), name));
            }
            self.extensions.push(Extension {
                target: target.to_string(),
                item: pi,
                origin: origin.clone(),
            });
        }
    }
}

/// Whether template `t` uses its parameter `name` as a part: a `part NAME`
/// block (markers it adds to that part) or a reference `NAME.marker` in an
/// element.
fn is_part_param(t: &TemplateDecl, name: &str) -> bool {
    t.items.iter().any(|item| match &item.kind {
        ItemKind::Part(p) => !p.ground && p.name.name == name,
        ItemKind::Element(e) => e
            .props
            .iter()
            .any(|p| matches!(&p.value, Value::Ref(r) if r.part.name == name)),
        _ => false,
    })
}
