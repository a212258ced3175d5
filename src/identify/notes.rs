//! Remarks on a fit as data, worded once: [`FitNote`] on the whole fit
//! (its size, frozen directions, unknowns held at a bound, no convergence)
//! and [`ParamNote`] on one parameter (why it is not identified, or a remark
//! on its value). Every renderer (the `identify` table and JSON) prints
//! [`FitNote::text`] and [`ParamNote::words`], never its own sentence.

use super::round_sig;

/// A value found outside the bounds declared with `unknown [lo, hi]`, boundary
/// units.
#[derive(Debug, Clone, PartialEq)]
pub struct OutsideBounds {
    /// The unknown's label (`A.k_x`, or `A.k_x = A.k_y` for a tied pair).
    pub unknown: String,
    pub value: f64,
    /// Boundary unit of the value and the bounds (`N/mm`).
    pub unit: String,
    /// The declared bounds; `None` is open.
    pub lower: Option<f64>,
    pub upper: Option<f64>,
}

impl OutsideBounds {
    pub fn words(&self) -> String {
        let b = |x: Option<f64>| x.map_or("open".to_string(), |x| format!("{}", round_sig(x, 6)));
        format!(
            "{} = {} {} lies outside its declared bounds [{}, {}]",
            self.unknown,
            round_sig(self.value, 6),
            self.unit,
            b(self.lower),
            b(self.upper)
        )
    }
}

/// The regression of one address by the iterative method: measured
/// deformation against simulated force along one bushing axis.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisRegression {
    /// The address (`A.k_x`).
    pub name: String,
    /// `None` when the deformation or the force has no spread to correlate.
    pub fit: Option<AxisFit>,
}

/// A regression's correlation and its offset (the deformation at zero force).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisFit {
    /// Correlation coefficient.
    pub r: f64,
    /// Offset in `unit`.
    pub offset: f64,
    /// `mm` for a translational axis, `deg` for a rotational one.
    pub unit: &'static str,
}

impl AxisRegression {
    pub fn words(&self) -> String {
        match self.fit {
            Some(AxisFit { r, offset, unit }) => format!(
                "{}: r = {r:.3}, offset {:.4} {unit}",
                self.name,
                // No "-0.0000" for an offset that rounds to zero.
                if offset.is_finite() && offset.abs() >= 5e-5 {
                    offset
                } else {
                    0.0
                }
            ),
            None => format!("{}: no deformation or force spread to correlate", self.name),
        }
    }
}

/// Why one parameter is not identified, or a remark on its value; worded once
/// in [`ParamNote::words`]. Values are in boundary units.
#[derive(Debug, Clone, PartialEq)]
pub enum ParamNote {
    /// Direct: only combinations with these other linear unknowns are
    /// determined (see the determined combinations).
    OnlyCombined { with: Vec<String> },
    /// Direct: the measured equilibria do not deform the element along this
    /// direction (its column is zero).
    NotDeformed,
    /// Direct: it does not affect the measured equilibria.
    NoEffect,
    /// Direct: the solution is not a finite number.
    NotFinite,
    /// Direct: a stiffness the equations determine as `value`, not positive.
    NotPositive { value: f64 },
    /// Direct: a stiffness whose 95 % half-width is `half_width_percent` of
    /// its value (more than half).
    Imprecise { half_width_percent: f64 },
    /// Iterative: the regression of each address; `kept_below` is the
    /// correlation threshold when no axis reached it, so the value was kept.
    Regression {
        axes: Vec<AxisRegression>,
        kept_below: Option<f64>,
    },
    /// Least squares: held at its declared bound `value` (the data pull it
    /// beyond), with no interval.
    HeldAtBound {
        upper: bool,
        value: f64,
        unit: String,
    },
    /// Least squares: in the null space of the weighted Jacobian.
    NotObserved,
    /// Least squares: its 95 % interval is too wide; `relative_half_width` of
    /// the fitted value.
    WideInterval {
        relative_half_width: f64,
        fitted: f64,
    },
    /// Direct and iterative (which do not enforce bounds): a value outside the
    /// declared bounds.
    OutsideBounds(OutsideBounds),
}

impl ParamNote {
    pub fn words(&self) -> String {
        match self {
            ParamNote::OnlyCombined { with } => format!(
                "not determined on its own: only combinations with {} are (see determined combinations)",
                with.join(", ")
            ),
            ParamNote::NotDeformed => "not determined: the measured equilibria do not deform the element this way (zero column)".into(),
            ParamNote::NoEffect => "not determined: it does not affect the measured equilibria".into(),
            ParamNote::NotFinite => "the solution is not a finite number".into(),
            ParamNote::NotPositive { value } => format!(
                "determined by the equations but came out {} (not positive): the data do not support a stiffness here",
                round_sig(*value, 4)
            ),
            ParamNote::Imprecise { half_width_percent } => format!(
                "determined by the equations but not by the data's precision (95 % half-width {half_width_percent:.0} % of the value)"
            ),
            ParamNote::Regression { axes, kept_below } => {
                let detail = axes.iter().map(AxisRegression::words).collect::<Vec<_>>().join("; ");
                match kept_below {
                    Some(t) => format!("kept its value: correlation below {t} ({detail})"),
                    None => detail,
                }
            }
            ParamNote::HeldAtBound { upper, value, unit } => format!(
                "at its {} bound {} {unit}: the data pull it beyond the declared bounds, so it is held there and has no interval (the others' intervals assume it exact)",
                if *upper { "upper" } else { "lower" },
                round_sig(*value, 6),
            ),
            ParamNote::NotObserved => "not identifiable: it does not affect the observations".into(),
            ParamNote::WideInterval {
                relative_half_width,
                fitted,
            } => format!(
                "not identifiable from these data: its 95 % interval spans a factor {:.2} (fitted {fitted:.4e})",
                1.0 + relative_half_width.min(1e12)
            ),
            ParamNote::OutsideBounds(b) => b.words(),
        }
    }

    /// The notes of one parameter as one sentence, `None` when there are none.
    pub fn join(notes: &[ParamNote]) -> Option<String> {
        if notes.is_empty() {
            return None;
        }
        Some(
            notes
                .iter()
                .map(ParamNote::words)
                .collect::<Vec<_>>()
                .join("; "),
        )
    }
}

impl std::fmt::Display for ParamNote {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.words())
    }
}

/// A remark on a fit that scripts and `diagnose` reason about; worded once in
/// [`FitNote::text`].
#[derive(Debug, Clone, PartialEq)]
pub enum FitNote {
    /// A value outside its declared bounds, from a method that does not
    /// enforce them.
    OutsideBounds {
        bounds: OutsideBounds,
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
            FitNote::OutsideBounds { bounds, method } => format!(
                "warning: {}; the {method} method does not enforce bounds (least squares does), and -o keeps the model's value",
                bounds.words()
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
