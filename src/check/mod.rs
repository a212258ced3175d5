//! Syntax tree → checked [`Model`]: resolves names, checks units and converts
//! them to internal units, builds frames, checks every element and the mobility
//! of the mechanism. Collects every problem instead of stopping at the first,
//! and keeps what it could check ([`Analysis`]) for tools such as the language
//! server: the partial model and a table of definitions and references.

mod attribution;
mod bushing;
mod elements;
mod error;
mod eval;
mod expand;
mod far_markers;
mod friction;
mod instance_scope;
pub use friction::{allows as friction_allows, motion_word as friction_motion_word};
mod geometry;
mod loads;
mod mirror;
pub use mirror::mirror_frame;
mod mobility;
mod parts;
mod props;
mod resolution;
pub mod validate;

pub use elements::properties;
pub use resolution::{Resolution, Symbol};

pub(crate) use eval::plain_number;

/// The largest magnitude (internal units) of dimension `dim` any suspension
/// comes near, and the limit as words (`"10 MN"`); None for a dimension
/// without one. Shared by the checker (E0214), the data readers and the
/// statics' own input checks, so every door rejects the same values.
pub fn plausible_limit(dim: crate::units::Dim) -> Option<(f64, &'static str)> {
    error::PLAUSIBLE
        .iter()
        .find(|(d, ..)| *d == dim)
        .map(|&(_, limit, shown)| (limit, shown))
}

use crate::diagnostic::{Diagnostic, Problems};
use crate::model::{ElementId, LoadSetId, Model, Param, ParamId};
use crate::source::SourceMap;
use crate::span::{FileId, Span};
use crate::syntax::ast::{File, Ident, ItemKind};

/// The result of checking a file: the model when there is no error, and every
/// diagnostic found (warnings do not prevent a model).
pub struct Checked {
    pub model: Option<Model>,
    pub problems: Problems,
}

/// The optional, expensive passes of a check.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Passes {
    /// The mobility analysis (an SVD of the constraint Jacobian at design):
    /// `axle check` and every command run it; the language server only on save.
    pub mobility: bool,
}

impl Passes {
    pub const ALL: Passes = Passes { mobility: true };
    /// What an editor needs on every keystroke.
    pub const FAST: Passes = Passes { mobility: false };
}

/// Everything a check found out, also when the file has errors.
pub struct Analysis {
    /// The syntax tree of the file (with a syntax error: the items that parsed).
    pub ast: File,
    /// The model as far as it could be checked: elements with errors are missing
    /// or hold placeholder values. Only a model without errors is simulated.
    pub model: Model,
    /// With syntax errors, only those: the checker's findings on a partial tree
    /// would be misleading (a part cut off by a syntax error is not unknown).
    pub problems: Problems,
    /// Definitions and references of names, with their spans.
    pub resolution: Resolution,
    /// The file had no syntax error: the tree is the whole file.
    pub parsed: bool,
}

/// Parses and checks a file of the source map; imported stdlib modules are added
/// to the map so their diagnostics can be rendered.
pub fn check_file(sources: &mut SourceMap, file: FileId) -> Checked {
    let a = analyse(sources, file, Passes::ALL);
    let model = (!a.problems.has_errors()).then_some(a.model);
    Checked {
        model,
        problems: a.problems,
    }
}

/// Parses and checks a file, keeping the partial model and the name table.
pub fn analyse(sources: &mut SourceMap, file: FileId, passes: Passes) -> Analysis {
    check_depth(sources, file, 0, passes)
}

/// Parses and checks a text; convenient for tests and tools.
pub fn check_str(name: &str, text: &str) -> (SourceMap, Checked) {
    let mut sources = SourceMap::new();
    let id = sources.add(name, text);
    let checked = check_file(&mut sources, id);
    (sources, checked)
}

fn check_depth(sources: &mut SourceMap, file: FileId, depth: usize, passes: Passes) -> Analysis {
    let text = sources.text(file).to_string();
    let parsed = crate::syntax::parse_collecting(file, &text);
    let ast = parsed.ast;
    let syntax_errors = parsed.errors;
    let mut problems = Problems::default();
    // Templates of imported modules, for the instances of this file.
    let mut imported_templates = Vec::new();
    let mut imports = Vec::new();
    let mut resolution = Resolution::default();
    for item in &ast.items {
        if let ItemKind::Import(name) = &item.kind {
            let Some(src) = crate::stdlib::module(&name.name) else {
                problems.push(error::unknown_module(
                    &name.name,
                    name.span,
                    crate::stdlib::MODULES.iter().map(|(n, _)| *n),
                ));
                continue;
            };
            if depth > 8 {
                problems.push(
                    Diagnostic::error("E0110", "imports nest too deeply (a cycle?)")
                        .primary(name.span, "imported here"),
                );
                continue;
            }
            let fname = crate::stdlib::file_name(&name.name);
            let fid = sources
                .find(&fname)
                .unwrap_or_else(|| sources.add(fname, src));
            let sub = check_depth(sources, fid, depth + 1, passes);
            let usable = !sub.problems.has_errors();
            imported_templates.extend(
                sub.ast
                    .items
                    .iter()
                    .filter(|i| matches!(i.kind, ItemKind::Template(_)))
                    .cloned(),
            );
            problems.extend(sub.problems);
            resolution.module(name.span, sub.ast.span);
            if usable {
                imports.push((name.clone(), sub.model));
            }
        }
    }
    // Templates and instances become plain items; the checker reads those.
    let mut expansion = expand::expand(&ast, &imported_templates);
    let flat = File {
        items: std::mem::take(&mut expansion.items),
        span: ast.span,
    };
    for d in std::mem::take(&mut expansion.problems) {
        problems.push(d);
    }
    let stem = std::path::Path::new(sources.name(file))
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "model".into());
    let mut checker = Checker {
        problems,
        model: Model {
            name: stem,
            ..Model::default()
        },
        library: !flat
            .items
            .iter()
            .any(|i| matches!(i.kind, ItemKind::Part(_))),
        file_span: ast.span,
        param_decls: flat
            .items
            .iter()
            .filter_map(|i| match &i.kind {
                ItemKind::Param(p) => Some((p.name.name.clone(), p.name.span)),
                _ => None,
            })
            .collect(),
        bad_markers: Default::default(),
        failed_params: Vec::new(),
        passes: Passes {
            // Only a file that parsed has a meaningful mobility.
            mobility: passes.mobility && syntax_errors.is_empty(),
        },
        resolution,
        mirrored_parts: std::mem::take(&mut expansion.mirrored_parts),
        mirrored_markers: std::mem::take(&mut expansion.mirrored_markers),
    };
    checker.run(&flat, imports);
    let Checker {
        mut problems,
        model,
        mut resolution,
        ..
    } = checker;
    let parsed = syntax_errors.is_empty();
    problems.list = attribution::attribute(problems.list, &expansion.instances);
    if !parsed {
        problems = Problems {
            list: syntax_errors,
        };
    }
    resolution.definitions(&model);
    Analysis {
        ast,
        model,
        problems,
        resolution,
        parsed,
    }
}

pub(crate) struct Checker {
    pub(crate) problems: Problems,
    pub(crate) model: Model,
    /// A file without parts (a stdlib module of load sets): no ground needed,
    /// wheel channels stay aimed at the using model's wheel.
    pub(crate) library: bool,
    pub(crate) file_span: Span,
    /// Every `param` of the file with its name's span, to tell a parameter used
    /// before its declaration from an unknown one.
    pub(crate) param_decls: Vec<(String, Span)>,
    /// Markers whose position or orientation could not be read (an error was
    /// reported): they stand at the origin, so geometry checks skip them.
    pub(crate) bad_markers: std::collections::BTreeSet<crate::model::MarkerId>,
    /// Parameters whose value could not be evaluated (an error was reported).
    pub(crate) failed_params: Vec<String>,
    pub(crate) passes: Passes,
    /// References found while resolving names.
    pub(crate) resolution: Resolution,
    /// Parts of mirrored instances (expanded names), see `mirror`.
    pub(crate) mirrored_parts: std::collections::BTreeSet<String>,
    /// `(ground, marker)` added to the ground by mirrored instances.
    pub(crate) mirrored_markers: std::collections::BTreeSet<(String, String)>,
}

impl Checker {
    fn run(&mut self, ast: &File, imports: Vec<(Ident, Model)>) {
        let mut default = None;
        for item in &ast.items {
            match &item.kind {
                ItemKind::Model(name) => self.model.name = name.name.clone(),
                ItemKind::DefaultLoads(name) => default = Some(name.clone()),
                ItemKind::Param(p) => self.param(p),
                _ => {}
            }
        }
        self.model.imports = imports
            .iter()
            .map(|(n, _)| crate::model::Import {
                module: n.name.clone(),
            })
            .collect();
        self.parts(ast);
        self.mirror(ast);
        self.elements(ast);
        self.loads(ast, imports);
        self.default_loads(default);
        if !self.library {
            // Geometry is checked even after other errors (every error of a run is
            // reported), on the elements whose markers were read without error.
            self.geometry();
            // Only a complete, geometrically consistent model has a meaningful mobility.
            if self.passes.mobility && !self.problems.has_errors() {
                self.mobility();
            }
        }
    }

    fn param(&mut self, p: &crate::syntax::ast::ParamDecl) {
        if let Some(first) = self.model.param_named(&p.name.name) {
            let span = self.span_of(ElementId::Param(first));
            self.problems.push(error::duplicate(
                "parameter",
                &p.name.name,
                p.name.span,
                span,
            ));
            return;
        }
        let Some(q) = self.eval(&p.value) else {
            // Its error is reported; uses of it would only repeat it as "unknown".
            self.failed_params.push(p.name.name.clone());
            return;
        };
        let unknown = p.unknown.as_ref().map(|u| {
            let mut bounds = crate::model::Bounds::default();
            if let Some((lo, hi)) = &u.bounds {
                let example = format!("{} {}", 1, q.dim.boundary_unit());
                bounds.lower = lo
                    .as_ref()
                    .and_then(|e| self.scalar(e, q.dim, &example))
                    .map(|v| v.value);
                bounds.upper = hi
                    .as_ref()
                    .and_then(|e| self.scalar(e, q.dim, &example))
                    .map(|v| v.value);
                if let (Some(l), Some(h)) = (bounds.lower, bounds.upper) {
                    if l >= h || q.value < l || q.value > h {
                        self.problems.push(
                            Diagnostic::error(
                                "E0211",
                                format!("the bounds of `{}` do not contain its value", p.name.name),
                            )
                            .primary(u.span, "lower bound, value and upper bound must increase")
                            .secondary(p.value.span, "the value"),
                        );
                    }
                }
            }
            bounds
        });
        let id = ElementId::Param(ParamId(self.model.params.len() as u32));
        self.model.origins.insert(id, p.name.span);
        self.model.params.push(Param {
            name: p.name.name.clone(),
            value: q.value,
            dim: q.dim,
            unknown,
        });
    }

    /// Resolves a parameter reference, reporting an unknown name.
    pub(crate) fn param_id(&mut self, name: &Ident) -> Option<ParamId> {
        match self.model.param_named(&name.name) {
            Some(id) => {
                self.resolution.refer(name.span, ElementId::Param(id));
                Some(id)
            }
            None if self.failed_params.contains(&name.name) => None,
            None => {
                let later = self
                    .param_decls
                    .iter()
                    .find(|(n, s)| n == &name.name && s.start > name.span.start);
                let d = if let Some((_, decl)) = later {
                    Diagnostic::error(
                        "E0111",
                        format!("parameter `{}` is used before its declaration", name.name),
                    )
                    .primary(name.span, "used here")
                    .secondary(*decl, "declared later here")
                    .hint("move the `param` line above its first use")
                } else if crate::units::base_unit(&name.name).is_some() {
                    // `13875 N / mm` reads `mm` as a name: the unit had spaces in it.
                    error::unknown_name("parameter", &name.name, name.span, [])
                        .note(format!("`{}` is a unit, but a unit is written right after its number without spaces", name.name))
                        .hint("write compound units without spaces: `13875 N/mm`, `4000 N*mm/deg`")
                } else {
                    error::unknown_name(
                        "parameter",
                        &name.name,
                        name.span,
                        self.model.params.iter().map(|p| p.name.as_str()),
                    )
                    .note("parameters are declared with `param NAME = VALUE` before they are used")
                };
                self.problems.push(d);
                None
            }
        }
    }

    fn default_loads(&mut self, default: Option<Ident>) {
        self.model.default_load_set = match default {
            Some(name) => match self.model.load_set_named(&name.name) {
                Some(id) => {
                    self.resolution.refer(name.span, ElementId::LoadSet(id));
                    Some(id)
                }
                None => {
                    let d = error::unknown_name(
                        "load set",
                        &name.name,
                        name.span,
                        self.model.load_sets.iter().map(|s| s.name.as_str()),
                    );
                    self.problems.push(d);
                    None
                }
            },
            // The first set written in the file, else the first imported one.
            None => (0..self.model.load_sets.len())
                .map(|i| LoadSetId(i as u32))
                .find(|id| !self.model.imported_load_sets.contains(id))
                .or_else(|| (!self.model.load_sets.is_empty()).then_some(LoadSetId(0))),
        };
    }

    pub(crate) fn span_of(&self, id: ElementId) -> Span {
        self.model.origins.get(id).unwrap_or(self.file_span)
    }
}

#[cfg(test)]
mod tests;
