//! Load sets: tables (one row per case) and sweeps (load paths), with channels
//! resolved to wheels and markers.

use super::Checker;
use super::error;
use crate::diagnostic::Diagnostic;
use crate::model::*;
use crate::span::Span;
use crate::syntax::ast::{ChannelLit, File, Ident, ItemKind, LoadsBody, LoadsDecl};
use crate::units::Dim;

/// More steps than this in one sweep is almost surely a unit mistake.
const MAX_SWEEP_STEPS: usize = 100_000;

impl Checker {
    pub(super) fn loads(&mut self, ast: &File, imports: Vec<(Ident, Model)>) {
        for (import, m) in imports {
            // A module's wheel loads go to the model's only wheel: with none or
            // several, say so once for the import, not once per set.
            let wheel_sets: Vec<&str> = m
                .load_sets
                .iter()
                .filter(|s| {
                    s.channels
                        .iter()
                        .any(|c| c.target == LoadTarget::DefaultWheel)
                })
                .map(|s| s.name.as_str())
                .collect();
            if !self.library && !wheel_sets.is_empty() && self.model.wheels.len() != 1 {
                self.problems
                    .push(self.imported_wheel_loads(&import, &wheel_sets));
                continue;
            }
            for (k, set) in m.load_sets.into_iter().enumerate() {
                let written = m.origins.get(ElementId::LoadSet(LoadSetId(k as u32)));
                self.add_imported_set(&import, set, written);
            }
        }
        for item in &ast.items {
            if let ItemKind::Loads(l) = &item.kind {
                self.load_set(l);
            }
        }
    }

    /// `written`: where the module defines the set, for go-to-definition.
    fn add_imported_set(&mut self, import: &Ident, mut set: LoadSet, written: Option<Span>) {
        if let Some(first) = self.model.load_set_named(&set.name) {
            let span = self.span_of(ElementId::LoadSet(first));
            self.problems.push(
                error::duplicate("load set", &set.name, import.span, span).note(format!(
                    "`{}` is also defined by module `{}`",
                    set.name, import.name
                )),
            );
            return;
        }
        let n_sets = self.model.load_sets.len() as u32;
        for ch in &mut set.channels {
            if ch.target == LoadTarget::DefaultWheel && !self.library {
                match self.default_wheel(import.span, &set.name) {
                    Some(w) => ch.target = LoadTarget::Wheel(w),
                    None => return,
                }
            }
        }
        let id = LoadSetId(n_sets);
        self.model
            .origins
            .insert(ElementId::LoadSet(id), import.span);
        if let Some(w) = written {
            self.resolution.defined_in_module(ElementId::LoadSet(id), w);
        }
        self.model.imported_load_sets.push(id);
        self.model.load_sets.push(set);
    }

    fn imported_wheel_loads(&self, import: &Ident, sets: &[&str]) -> Diagnostic {
        let wheels: Vec<String> = self
            .model
            .wheels
            .iter()
            .map(|w| format!("`{}`", w.name))
            .collect();
        let (code, found) = if wheels.is_empty() {
            ("E0501", "the model has no wheel".to_string())
        } else {
            (
                "E0502",
                format!(
                    "the model has {} wheels: {}",
                    wheels.len(),
                    wheels.join(", ")
                ),
            )
        };
        Diagnostic::error(
            code,
            format!("module `{}` loads the model's only wheel, but {found}", import.name),
        )
        .primary(import.span, "imported here")
        .note(format!("its wheel-load sets: {}", sets.join(", ")))
        .hint(if wheels.is_empty() {
            "declare the wheel (`wheel NAME { ... }` with `centre` and `contact` markers)".to_string()
        } else {
            "stdlib sets are written for a half axle with one wheel; write your own sets naming the wheel, e.g. `left.fz`".to_string()
        })
    }

    /// The wheel whose (possibly qualified) name is `path` joined with dots.
    fn wheel_named(&self, path: &[String]) -> Option<usize> {
        let name = path.join(".");
        self.model.wheels.iter().position(|w| w.name == name)
    }

    /// The model's only wheel, for channels written without a wheel name.
    fn default_wheel(&mut self, span: Span, set: &str) -> Option<WheelId> {
        match self.model.wheels.len() {
            1 => Some(WheelId(0)),
            0 => {
                self.problems.push(
                    Diagnostic::error("E0501", format!("load set `{set}` applies wheel loads, but the model has no wheel"))
                        .primary(span, "wheel loads used here")
                        .hint("declare a wheel (`wheel NAME { ... }` with `centre` and `contact` markers), or load a marker: `part.marker.fz`"),
                );
                None
            }
            _ => {
                let names: Vec<String> = self
                    .model
                    .wheels
                    .iter()
                    .map(|w| format!("`{}.fz`", w.name))
                    .collect();
                self.problems.push(
                    Diagnostic::error(
                        "E0502",
                        format!("load set `{set}` does not say which wheel it loads"),
                    )
                    .primary(span, "the model has several wheels")
                    .hint(format!(
                        "name the wheel in the channel: {}",
                        names.join(", ")
                    )),
                );
                None
            }
        }
    }

    fn channel(&mut self, c: &ChannelLit, set: &str) -> Option<Channel> {
        let comp_name = c.path.last().map(String::as_str).unwrap_or("");
        let Some(component) = Component::from_name(comp_name) else {
            self.problems.push(
                error::unknown_name(
                    "load component",
                    comp_name,
                    c.span,
                    Component::ALL.iter().map(|c| c.name()),
                )
                .note("components: fx, fy, fz (N), mx, my, mz (N*mm), global axes"),
            );
            return None;
        };
        let target = match c.path.len() {
            1 if self.library => LoadTarget::DefaultWheel,
            1 => LoadTarget::Wheel(self.default_wheel(c.span, set)?),
            n if n == 2 || self.wheel_named(&c.path[..n - 1]).is_some() => {
                let w = &c.path[..n - 1].join(".");
                match self.wheel_named(&c.path[..n - 1]) {
                    Some(i) => {
                        let at = Span::new(
                            c.span.file,
                            c.span.start as usize,
                            c.span.start as usize + w.len(),
                        );
                        self.resolution
                            .refer(at, ElementId::Wheel(WheelId(i as u32)));
                        LoadTarget::Wheel(WheelId(i as u32))
                    }
                    None => {
                        let mut d = error::unknown_name(
                            "wheel",
                            w,
                            c.span,
                            self.model.wheels.iter().map(|w| w.name.as_str()),
                        );
                        if self.model.wheels.is_empty() {
                            d = d.note("the model has no wheel: declare one with `wheel NAME { ... }` and its `centre` and `contact` markers, or load a marker with `PART.MARKER.fz`");
                        } else if suggest_none(w, &self.model.wheels) {
                            let names: Vec<&str> =
                                self.model.wheels.iter().map(|w| w.name.as_str()).collect();
                            d = d.note(format!("wheels: {}", names.join(", ")));
                        }
                        if self.model.part_named(w).is_some() {
                            d = d.note(format!(
                                "`{w}` is a part; to load a marker write `{w}.MARKER.{comp_name}`"
                            ));
                        }
                        self.problems.push(d);
                        return None;
                    }
                }
            }
            n => {
                // `arm.tip.fx`, `front_left.upright.WC.fx`: the marker is the
                // name before the component, the part the names before it.
                let part = c.path[..n - 2].join(".");
                let marker = &c.path[n - 2];
                let r = crate::syntax::ast::MarkerRef {
                    part: Ident {
                        name: part.clone(),
                        span: c.span,
                    },
                    marker: Ident {
                        name: marker.clone(),
                        span: c.span,
                    },
                    span: c.span,
                };
                // The channel is one token (no spaces): the names sit at known
                // offsets inside it.
                let start = c.span.start as usize;
                let part_end = start + part.len();
                let marker_start = part_end + 1;
                let names = (
                    Span::new(c.span.file, start, part_end),
                    Span::new(c.span.file, marker_start, marker_start + marker.len()),
                );
                LoadTarget::Marker(self.marker_ref_at(&r, names)?)
            }
        };
        Some(Channel { target, component })
    }

    fn component_dim(c: Component) -> Dim {
        if c.is_torque() {
            Dim::TORQUE
        } else {
            Dim::FORCE
        }
    }

    fn load_set(&mut self, l: &LoadsDecl) {
        let name = &l.name.name;
        if let Some(first) = self.model.load_set_named(name) {
            let span = self.span_of(ElementId::LoadSet(first));
            self.problems
                .push(error::duplicate("load set", name, l.name.span, span));
            return;
        }
        let set = match &l.body {
            LoadsBody::Table { columns, rows } => {
                let mut channels = Vec::new();
                let mut factors = Vec::new();
                let mut ok = true;
                for (n, col) in columns.iter().enumerate() {
                    if let Some(prev) = columns[..n]
                        .iter()
                        .find(|c| c.channel.path == col.channel.path)
                    {
                        self.problems.push(error::duplicate(
                            "column",
                            &col.channel.text(),
                            col.channel.span,
                            prev.channel.span,
                        ));
                        ok = false;
                        continue;
                    }
                    let ch = self.channel(&col.channel, name);
                    let unit = self.unit(&col.unit);
                    match (ch, unit) {
                        (Some(ch), Some(u)) => {
                            let want = Self::component_dim(ch.component);
                            if u.dim != want {
                                let ex = format!("{} {}", col.channel.text(), want.boundary_unit());
                                self.problems.push(error::wrong_dimension(
                                    want,
                                    u.dim,
                                    col.unit.span,
                                    &ex,
                                ));
                                ok = false;
                            }
                            channels.push(ch);
                            factors.push(u.factor);
                        }
                        _ => ok = false,
                    }
                }
                let mut cases: Vec<LoadCase> = Vec::new();
                for (r, row) in rows.iter().enumerate() {
                    if let Some(prev) = rows[..r].iter().find(|x| x.name.name == row.name.name) {
                        self.problems.push(error::duplicate(
                            "load case",
                            &row.name.name,
                            row.name.span,
                            prev.name.span,
                        ));
                        ok = false;
                    }
                    if row.values.len() != columns.len() {
                        self.problems.push(
                            Diagnostic::error(
                                "E0503",
                                format!(
                                    "load case `{}` has {} values for {} columns",
                                    row.name.name,
                                    row.values.len(),
                                    columns.len()
                                ),
                            )
                            .primary(row.span, "wrong number of values")
                            .note(format!(
                                "columns: {}",
                                columns
                                    .iter()
                                    .map(|c| c.channel.text())
                                    .collect::<Vec<_>>()
                                    .join(", ")
                            )),
                        );
                        ok = false;
                        continue;
                    }
                    let values: Vec<f64> = row
                        .values
                        .iter()
                        .zip(&factors)
                        .map(|(v, f)| v.value * f)
                        .collect();
                    // Each cell judged at its column: `1e400` overflows to
                    // infinity, `1e200` is finite but no load.
                    for ((v, x), ch) in row.values.iter().zip(&values).zip(&channels) {
                        let dim = Self::component_dim(ch.component);
                        let bad = if x.is_finite() {
                            error::beyond_any_suspension(*x, dim, v.span)
                        } else {
                            Some(error::bad_number("this value", v.span, "is not finite"))
                        };
                        if let Some(d) = bad {
                            self.problems.push(d);
                            ok = false;
                        }
                    }
                    cases.push(LoadCase {
                        name: row.name.name.clone(),
                        values,
                    });
                }
                if rows.is_empty() {
                    self.problems.push(
                        Diagnostic::error("E0504", format!("load set `{name}` has no cases"))
                            .primary(l.name.span, "empty"),
                    );
                    ok = false;
                }
                if !ok {
                    return;
                }
                LoadSet {
                    name: name.clone(),
                    channels,
                    cases,
                    form: LoadForm::Table,
                }
            }
            LoadsBody::Sweep { lines } => match self.sweep(name, l.name.span, lines) {
                Some(s) => s,
                None => return,
            },
        };
        let id = LoadSetId(self.model.load_sets.len() as u32);
        self.model
            .origins
            .insert(ElementId::LoadSet(id), l.name.span);
        self.model.load_sets.push(set);
    }

    fn sweep(
        &mut self,
        name: &str,
        name_span: Span,
        lines: &[crate::syntax::ast::SweepLine],
    ) -> Option<LoadSet> {
        let mut channels = Vec::new();
        let mut constants = Vec::new();
        // Each swept line: its channel index, waypoints, step and span.
        let mut swept: Vec<(usize, Vec<f64>, f64, Span)> = Vec::new();
        let mut ok = true;
        for (n, line) in lines.iter().enumerate() {
            if let Some(prev) = lines[..n]
                .iter()
                .find(|x| x.channel.path == line.channel.path)
            {
                self.problems.push(error::duplicate(
                    "channel",
                    &line.channel.text(),
                    line.channel.span,
                    prev.channel.span,
                ));
                ok = false;
                continue;
            }
            let Some(ch) = self.channel(&line.channel, name) else {
                ok = false;
                continue;
            };
            let dim = Self::component_dim(ch.component);
            let ex = format!("{} 4500 {}", line.channel.text(), dim.boundary_unit());
            let pts: Vec<Option<Val>> = line
                .waypoints
                .iter()
                .map(|e| self.scalar(e, dim, &ex))
                .collect();
            let Some(pts) = pts.into_iter().collect::<Option<Vec<Val>>>() else {
                ok = false;
                continue;
            };
            let pts: Vec<f64> = pts.iter().map(|v| v.value).collect();
            match (&line.step, pts.len()) {
                (None, 1) => {
                    channels.push(ch);
                    constants.push((channels.len() - 1, pts[0]));
                }
                (Some(step), n) if n >= 2 => {
                    let Some(s) = self.scalar(step, dim, &ex) else {
                        ok = false;
                        continue;
                    };
                    if s.value <= 0.0 {
                        self.problems.push(error::bad_number(
                            "the step",
                            step.span,
                            "must be positive",
                        ));
                        ok = false;
                        continue;
                    }
                    channels.push(ch);
                    swept.push((channels.len() - 1, pts, s.value, line.span));
                }
                (Some(_), _) => {
                    self.problems.push(
                        Diagnostic::error("E0506", "a swept channel needs at least two waypoints")
                            .primary(line.span, "only one value before `by`")
                            .hint("write `fz 1000 N -> 8000 N by 250 N`"),
                    );
                    ok = false;
                }
                (None, _) => {
                    self.problems.push(
                        Diagnostic::error("E0507", "waypoints without a step")
                            .primary(line.span, "how large are the steps?")
                            .hint("end the line with `by 250 N`"),
                    );
                    ok = false;
                }
            }
        }
        if !ok {
            return None;
        }
        if swept.is_empty() {
            self.problems.push(
                Diagnostic::error("E0508", format!("sweep `{name}` sweeps no channel"))
                    .primary(name_span, "nothing varies")
                    .hint("add a line such as `fz 1000 N -> 8000 N by 250 N`"),
            );
            return None;
        }
        let mut paths = Vec::with_capacity(swept.len());
        for (idx, waypoints, step, span) in &swept {
            let dim = Self::component_dim(channels[*idx].component);
            paths.push(self.sweep_values(waypoints, *step, *span, dim)?);
        }
        // Several swept channels move together, step for step (both wheels of
        // an axle in parallel travel): every one must give as many cases.
        // (Every line gave one channel, in order: a channel index is its line's.)
        let (first, count) = (&swept[0], paths[0].len());
        for ((idx, _, _, span), path) in swept.iter().zip(&paths).skip(1) {
            if path.len() != count {
                self.problems.push(
                    Diagnostic::error(
                        "E0505",
                        format!("the swept channels of sweep `{name}` do not move in lockstep"),
                    )
                    .primary(*span, format!("{} cases", path.len()))
                    .secondary(first.3, format!("{count} cases"))
                    .note(format!(
                        "swept channels move together, one step each per case; `{}` and `{}` must give as many cases",
                        lines[first.0].channel.text(),
                        lines[*idx].channel.text()
                    ))
                    .hint("choose steps that divide each channel's travel into the same number of steps, or write a load table"),
                );
                return None;
            }
        }
        let cases = (0..count)
            .map(|k| {
                let mut vals = vec![0.0; channels.len()];
                for (c, x) in &constants {
                    vals[*c] = *x;
                }
                for ((idx, ..), path) in swept.iter().zip(&paths) {
                    vals[*idx] = path[k];
                }
                LoadCase {
                    name: format!("{name}_{:03}", k + 1),
                    values: vals,
                }
            })
            .collect();
        Some(LoadSet {
            name: name.to_string(),
            channels,
            cases,
            form: LoadForm::Sweep {
                swept: swept
                    .into_iter()
                    .map(|(channel, waypoints, step, _)| SweptChannel {
                        channel,
                        waypoints,
                        step,
                    })
                    .collect(),
            },
        })
    }

    /// The values of one swept channel: from waypoint to waypoint by `step`.
    fn sweep_values(
        &mut self,
        waypoints: &[f64],
        step: f64,
        span: Span,
        dim: Dim,
    ) -> Option<Vec<f64>> {
        let mut values = vec![waypoints[0]];
        for w in waypoints.windows(2) {
            let n = ((w[1] - w[0]).abs() / step).round();
            // Judged in floating point, before any count is converted or
            // allocated: `by 1e-300 N` gives n = 1e300.
            if !n.is_finite() || values.len() as f64 + n > MAX_SWEEP_STEPS as f64 {
                self.problems.push(bad_sweep(span));
                return None;
            }
            if ((w[1] - w[0]).abs() - n * step).abs() > 1e-9 * step.max(w[1].abs()) || n < 1.0 {
                self.problems.push(
                    Diagnostic::error(
                        "E0509",
                        "a waypoint is not a whole number of steps from the previous one",
                    )
                    .primary(span, "the steps do not land on every waypoint")
                    .note({
                        let (f, u) = (dim.boundary_factor(), dim.boundary_unit());
                        format!(
                            "from {} {u} to {} {u} by {} {u}",
                            w[0] / f,
                            w[1] / f,
                            step / f
                        )
                    }),
                );
                return None;
            }
            let dir = (w[1] - w[0]).signum();
            for k in 1..=(n as usize) {
                values.push(w[0] + dir * step * k as f64);
            }
        }
        Some(values)
    }
}

fn bad_sweep(span: Span) -> Diagnostic {
    Diagnostic::error(
        "E0510",
        format!("the sweep has more than {MAX_SWEEP_STEPS} steps"),
    )
    .primary(span, "too many steps")
    .hint("check the step and its unit")
}

/// No wheel name is close enough to `name` for a "did you mean".
fn suggest_none(name: &str, wheels: &[Wheel]) -> bool {
    crate::diagnostic::suggest::best(name, wheels.iter().map(|w| w.name.as_str())).is_none()
}
