//! Stiffness identification from measured equilibria (thesis chapters 4 and 5,
//! and a full least-squares method beyond them).
//!
//! Input: a checked [`Model`], the [`Unknown`]s to identify, and per step the
//! applied loads and the measured part poses ([`measured::Measured`]).
//! Output: an [`Identified`] result in internal units; the CLI converts to
//! boundary units. Three methods:
//! - [`direct`]: the equilibrium equations at the measured poses are linear in
//!   the stiffnesses; project them on the admissible motions and solve the
//!   stacked system by SVD (chapter 4);
//! - [`iterative`]: simulate, regress measured deformation against simulated
//!   force per bushing axis, repeat (chapter 5);
//! - [`lsq`]: Levenberg–Marquardt over any parameters against every landmark
//!   (and K&C channel), with exact sensitivities from the statics engine.
//!
//! What a method cannot determine is reported as such ([`ParamResult::value`]
//! is `None`, or the kept initial value with `identifiable: false`), never as a
//! number that looks identified.

pub mod columns;
pub mod combinations;
pub mod direct;
pub mod error;
pub mod fit_stats;
pub mod iterative;
pub mod linalg;
pub mod lsq;
pub mod measured;
pub mod notes;
pub mod observations;
pub mod report;
pub mod unknowns;

pub use error::{IdentifyError, IdentifyErrorKind};
pub use measured::{KcObservation, Measured, MeasuredStep};
pub use notes::{FitNote, ParamNote};
pub use unknowns::{Unknown, select_unknowns};

use crate::model::Model;

/// Which method produced a result.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    Direct,
    Iterative,
    Lsq,
}

impl Method {
    pub fn name(self) -> &'static str {
        match self {
            Method::Direct => "direct",
            Method::Iterative => "iterative",
            Method::Lsq => "lsq",
        }
    }
}

/// The outcome for one unknown, internal units.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamResult {
    pub initial: f64,
    /// The identified value; `None` when the data do not determine it.
    pub value: Option<f64>,
    /// 95 % interval, when the method estimates one.
    pub interval: Option<(f64, f64)>,
    pub identifiable: bool,
    /// Why a parameter is not identified, or remarks on its value, in the
    /// order they are printed ([`ParamNote::join`]).
    pub notes: Vec<ParamNote>,
    /// The value's relation to the unknown's declared bounds, when it is not
    /// plainly inside them.
    pub bound: Option<BoundIssue>,
}

/// A value at or beyond the bounds declared with `unknown [lo, hi]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BoundIssue {
    /// Least squares held it at the bound (the data pull it beyond).
    AtLower,
    AtUpper,
    /// A method that does not enforce bounds (direct, iterative) found it outside.
    BelowLower,
    AboveUpper,
}

/// Direct and iterative solve without bounds (a linear system, a regression):
/// a value outside its unknown's declared bounds is flagged with a note, never
/// returned silently as if it were admissible.
pub(crate) fn flag_outside_bounds(r: &mut Identified) {
    for (u, p) in r.unknowns.iter().zip(r.params.iter_mut()) {
        let Some(v) = p.value else { continue };
        let issue = match (u.bounds.lower, u.bounds.upper) {
            (Some(lo), _) if v < lo => BoundIssue::BelowLower,
            (_, Some(hi)) if v > hi => BoundIssue::AboveUpper,
            _ => continue,
        };
        let b = |x: Option<f64>| x.map(|x| crate::units::to_boundary(x, u.dim));
        let bounds = notes::OutsideBounds {
            unknown: u.label(),
            value: crate::units::to_boundary(v, u.dim),
            unit: u.dim.boundary_unit(),
            lower: b(u.bounds.lower),
            upper: b(u.bounds.upper),
        };
        // First, since it says the value is not admissible.
        p.notes.insert(0, ParamNote::OutsideBounds(bounds.clone()));
        p.bound = Some(issue);
        let note = FitNote::OutsideBounds {
            bounds,
            method: r.method.name(),
        };
        r.notes.push(note);
    }
}

/// A linear combination of unknowns the data determine when its terms are not
/// determined one by one: `Σ coefficient · parameter = value` (internal units).
#[derive(Debug, Clone, PartialEq)]
pub struct Combination {
    /// (parameter name, coefficient): coefficients apply to boundary units
    /// (N/mm, N·mm/deg, mm), the largest is 1.
    pub terms: Vec<(String, f64)>,
    /// Value of the combination in boundary units.
    pub value: f64,
    /// Boundary unit of the value (that of the largest term).
    pub unit: String,
}

impl Combination {
    /// `kt_x(b1) + kt_x(b2)` (`interfaces.md` style), coefficients other than
    /// ±1 written out.
    pub fn expression(&self) -> String {
        let mut out = String::new();
        for (k, (name, c)) in self.terms.iter().enumerate() {
            let term = match name.rsplit_once('.') {
                Some((e, f)) => format!("{f}({e})"),
                None => name.clone(),
            };
            let mag = c.abs();
            let coef = if (mag - 1.0).abs() < 1e-6 {
                String::new()
            } else {
                format!("{} ", round_sig(mag, 4))
            };
            if k == 0 {
                out.push_str(if *c < 0.0 { "-" } else { "" });
            } else {
                out.push_str(if *c < 0.0 { " - " } else { " + " });
            }
            out.push_str(&coef);
            out.push_str(&term);
        }
        out
    }
}

/// `x` rounded to `n` significant digits (for readable coefficients).
pub fn round_sig(x: f64, n: i32) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let e = x.abs().log10().floor() as i32;
    let f = 10f64.powi(n - 1 - e);
    (x * f).round() / f
}

/// One iteration of an iterative method: the unknowns' values (internal units).
#[derive(Debug, Clone, PartialEq)]
pub struct HistoryEntry {
    pub iteration: usize,
    pub values: Vec<f64>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Identified {
    pub method: Method,
    pub unknowns: Vec<Unknown>,
    /// One per unknown, same order.
    pub params: Vec<ParamResult>,
    pub combinations: Vec<Combination>,
    /// Numerical rank of the identification matrix (direct: [LD]; lsq: the
    /// weighted Jacobian; iterative: the number of accepted regressions).
    pub rank: usize,
    /// Singular values, largest first, of the column-scaled identification matrix.
    pub singular_values: Vec<f64>,
    pub iterations: usize,
    pub history: Vec<HistoryEntry>,
    /// Correlation matrix of the unknowns (lsq), row-major.
    pub correlation: Option<Vec<Vec<f64>>>,
    /// Root-mean-square weighted residual (lsq: a posteriori σ factor; 1 means
    /// the fit matches the stated noise).
    pub sigma0: Option<f64>,
    /// Remarks for the user (left-out data, restrictions applied).
    pub notes: Vec<FitNote>,
}

impl Identified {
    /// The model with every identified value written in (undetermined ones keep
    /// their initial value), for `-o`. A value outside its declared bounds is
    /// not written: the model would no longer check (E0211), and the result
    /// already warns about it.
    pub fn apply(&self, model: &Model) -> Model {
        let mut m = model.clone();
        for (u, p) in self.unknowns.iter().zip(&self.params) {
            if matches!(
                p.bound,
                Some(BoundIssue::BelowLower | BoundIssue::AboveUpper)
            ) {
                continue;
            }
            if let Some(v) = p.value {
                u.set(&mut m, v);
            }
        }
        m
    }
}
