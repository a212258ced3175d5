//! Failures of identification as data: a kind with a stable code (E11xx), the
//! sentence of the site that failed, the elements responsible, and the statics
//! failure underneath when a solve failed. Worded once here; rendered late.

use crate::diagnostic::Diagnostic;
use crate::model::{ElementId, Model};
use crate::statics::StaticsError;

/// What kind of failure; each has its code (`docs/language.md`, "codes").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IdentifyErrorKind {
    /// The measured data and the model do not fit together (steps without
    /// loads, case counts, no pose).
    Data,
    /// Command-line choices that cannot work (an unknown load set, no loads,
    /// a non-positive tolerance or start value).
    Options,
    /// Nothing to identify, or an unknown that names no field.
    Unknowns,
    /// The chosen method cannot identify this (iterative beyond bushings,
    /// direct with geometric unknowns, a part without a measured pose).
    Method,
    /// The data cannot determine the unknowns (too few observations, no
    /// admissible motion, an undetermined registration).
    Undetermined,
    /// The model does not solve; `source` holds the statics failure.
    Solve,
    /// An iteration did not converge.
    NotConverged,
    /// A matrix or a Jacobian is not finite or singular.
    Numeric,
    /// The `--report` plots cannot be drawn from these data.
    Report,
}

impl IdentifyErrorKind {
    pub fn code(self) -> &'static str {
        match self {
            IdentifyErrorKind::Data => "E1101",
            IdentifyErrorKind::Options => "E1102",
            IdentifyErrorKind::Unknowns => "E1103",
            IdentifyErrorKind::Method => "E1104",
            IdentifyErrorKind::Undetermined => "E1105",
            IdentifyErrorKind::Solve => "E1106",
            IdentifyErrorKind::NotConverged => "E1107",
            IdentifyErrorKind::Numeric => "E1108",
            IdentifyErrorKind::Report => "E1109",
        }
    }

    /// What the user can try, in one sentence.
    fn hint(self) -> Option<&'static str> {
        match self {
            IdentifyErrorKind::Method => Some("`--method lsq` identifies any addressable field"),
            IdentifyErrorKind::Undetermined => Some(
                "measure more load cases or more parts, or identify fewer unknowns (`--unknown`)",
            ),
            IdentifyErrorKind::NotConverged => {
                Some("start nearer (`--initial`) or loosen `--tolerance`")
            }
            _ => None,
        }
    }
}

/// A numeric or data failure of identification, naming the elements at fault.
#[derive(Debug, Clone, PartialEq)]
pub struct IdentifyError {
    pub kind: IdentifyErrorKind,
    /// What happened, in the words of the site that found it.
    pub message: String,
    pub elements: Vec<ElementId>,
    /// The statics failure underneath, when a solve failed.
    pub source: Option<StaticsError>,
    /// The diagnostic itself, when the failure is a bad address on the
    /// command line (`--unknown`), worded once by `AddressError`.
    pub address: Option<Box<Diagnostic>>,
}

impl IdentifyError {
    pub fn of(
        kind: IdentifyErrorKind,
        message: impl Into<String>,
        elements: Vec<ElementId>,
    ) -> IdentifyError {
        IdentifyError {
            kind,
            message: message.into(),
            elements,
            source: None,
            address: None,
        }
    }

    /// A bad address (`--unknown A.k_raidal`): its diagnostic is the one
    /// every command that takes an address gives (E0803).
    pub fn address(d: Diagnostic) -> IdentifyError {
        IdentifyError {
            address: Some(Box::new(d.clone())),
            ..IdentifyError::of(IdentifyErrorKind::Unknowns, d.message, vec![])
        }
    }

    /// A solve that failed: `context` says which (`step 3 at the trial values`).
    pub fn statics(context: impl Into<String>, e: StaticsError, model: &Model) -> IdentifyError {
        let context = context.into();
        let message = match context.is_empty() {
            true => e.message(model),
            false => format!("{context}: {}", e.message(model)),
        };
        IdentifyError {
            kind: IdentifyErrorKind::Solve,
            message,
            elements: e.elements.clone(),
            source: Some(e),
            address: None,
        }
    }

    /// The diagnostic: the code of the kind, the statics code underneath in a
    /// note, the first element with a source location as the primary label.
    pub fn to_diagnostic(&self, model: &Model) -> Diagnostic {
        if let Some(d) = &self.address {
            return (**d).clone();
        }
        let mut d = Diagnostic::error(self.kind.code(), self.message.clone());
        let mut primary = true;
        for &e in &self.elements {
            let what = model.describe(e);
            match model.origins.get(e) {
                Some(span) if primary => {
                    d = d.primary(span, format!("{what} is responsible"));
                    primary = false;
                }
                Some(span) => d = d.secondary(span, format!("{what} is involved")),
                None => d = d.note(format!("{what} has no source location (added by a tool)")),
            }
        }
        if let Some(s) = &self.source {
            d = d.note(format!(
                "the statics failure underneath is {}",
                s.kind.code()
            ));
        }
        match self.kind.hint() {
            Some(h) => d.hint(h),
            None => d,
        }
    }
}

impl std::fmt::Display for IdentifyError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

/// A remark on a fit that scripts and `diagnose` reason about; worded once in
/// [`FitNote::text`].
#[derive(Debug, Clone, PartialEq)]
pub enum FitNote {
    /// A value outside its declared bounds, from a method that does not
    /// enforce them: `text` is the value and the bounds.
    OutsideBounds {
        unknown: String,
        text: String,
        method: &'static str,
    },
    /// A `--report` plot and its RMS toe / camber against measured (deg).
    Report {
        path: String,
        steps: usize,
        initial: [f64; 2],
        identified: [f64; 2],
    },
    /// The size of a direct fit: steps, equations (per step after the joint
    /// reactions are eliminated), linear unknowns, rank.
    DirectSize {
        steps: usize,
        equations: usize,
        per_step: usize,
        unknowns: usize,
        rank: usize,
    },
    /// The size of a least-squares fit and its a posteriori sigma factor.
    LsqSize {
        observations: usize,
        unknowns: usize,
        registered: bool,
        sigma0: f64,
    },
    /// The iterative method converged to `tolerance` (relative).
    Converged { tolerance: f64, iterations: usize },
    /// Unknowns the iterative method left out (by label).
    NotIterative { unknowns: Vec<String> },
    /// An initial value outside the declared bounds, projected onto them
    /// (boundary units).
    StartsAtBound {
        unknown: String,
        value: f64,
        initial: f64,
    },
    /// The registration to the model frame re-estimated with the unknowns:
    /// its correction (mm, rad).
    Registered { translation: f64, angle: f64 },
    /// `count` directions of the parameter space with a singular value below
    /// `below` were not searched.
    Frozen { count: usize, below: f64 },
    /// The iteration limit was reached while a Gauss-Newton step would still
    /// move a variable by `remaining` standard errors.
    NotConverged { iterations: usize, remaining: f64 },
    /// `count` unknowns held at a declared bound, of `unknowns`.
    HeldAtBound { count: usize, unknowns: usize },
}

impl FitNote {
    pub fn text(&self) -> String {
        match self {
            FitNote::OutsideBounds { text, method, .. } => format!(
                "warning: {text}; the {method} method does not enforce bounds (least squares does), and -o keeps the model's value"
            ),
            FitNote::Report {
                path,
                steps,
                initial,
                identified,
            } => format!(
                "report {path}: {steps} measured steps; RMS toe / camber against measured: initial {:.4} / {:.4} deg, identified {:.4} / {:.4} deg",
                initial[0], initial[1], identified[0], identified[1]
            ),
            FitNote::DirectSize {
                steps,
                equations,
                per_step,
                unknowns,
                rank,
            } => format!(
                "{steps} steps, {equations} equations ({per_step} per step after eliminating the joint reactions), {unknowns} linear unknowns, rank {rank}"
            ),
            FitNote::LsqSize {
                observations,
                unknowns,
                registered,
                sigma0,
            } => format!(
                "{observations} independent observations (6 per fitted pose, 1 per K&C channel), {unknowns} unknowns{}; a posteriori sigma factor {sigma0:.3}",
                if *registered {
                    " and 6 registration variables"
                } else {
                    ""
                }
            ),
            FitNote::Converged {
                tolerance,
                iterations,
            } => format!("converged to relative tolerance {tolerance} in {iterations} iterations"),
            FitNote::NotIterative { unknowns } => format!(
                "not identified by the iterative method (not a bushing stiffness, or a part of the bushing has no measured pose): {}",
                unknowns.join(", ")
            ),
            FitNote::StartsAtBound {
                unknown,
                value,
                initial,
            } => format!(
                "{unknown} starts at its declared bound {value:.4e}: its initial value {initial:.4e} lies outside"
            ),
            FitNote::Registered { translation, angle } => format!(
                "the registration to the model frame (fitted from the ground's landmarks) was re-estimated with the unknowns, and its uncertainty is in their intervals: correction {translation:.4} mm, {angle:.2e} rad"
            ),
            FitNote::Frozen { count, below } => format!(
                "{count} direction(s) of the parameter space were not searched (singular value below {below}: one standard error there spans more than a factor e of the stiffnesses), so the parameters along them stay near their initial values and are not identifiable; the intervals include their uncertainty"
            ),
            FitNote::NotConverged {
                iterations,
                remaining,
            } => format!(
                "not converged in {iterations} iterations: a Gauss–Newton step would still move a variable by {remaining:.2} standard errors (a sloppy, curved valley of parameters the data hardly determine); the intervals are taken at the last iterate"
            ),
            FitNote::HeldAtBound { count, unknowns } => format!(
                "{count} unknown(s) held at a declared bound; rank and singular values are of the other {}",
                unknowns - count
            ),
        }
    }
}

impl std::fmt::Display for FitNote {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.text())
    }
}
