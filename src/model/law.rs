//! Scalar force laws shared by bushings, springs and stops: linear with a cubic
//! term, polynomial, or a monotone table with linear extrapolation.

use super::param::Val;

/// A table of `(x, y)` points, x strictly increasing, at least two points,
/// internal units. Evaluated by linear interpolation and linear extrapolation.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    pub points: Vec<(f64, f64)>,
}

impl Table {
    /// Value and slope at `x`.
    pub fn eval(&self, x: f64) -> (f64, f64) {
        let p = &self.points;
        let n = p.len();
        if n < 2 {
            return (p.first().map_or(0.0, |q| q.1), 0.0);
        }
        // Segment index: the last segment whose left end is <= x, clamped so the
        // end segments extrapolate.
        let i = match p.iter().position(|q| q.0 > x) {
            Some(0) => 0,
            Some(k) => (k - 1).min(n - 2),
            None => n - 2,
        };
        let (x0, y0) = p[i];
        let (x1, y1) = p[i + 1];
        let slope = (y1 - y0) / (x1 - x0);
        (y0 + slope * (x - x0), slope)
    }
}

/// Restoring-force law along one axis: force as a function of deformation `d`
/// (already offset), returned as the magnitude that resists `d`.
#[derive(Debug, Clone, PartialEq)]
pub enum AxisLaw {
    /// `f(d) = k d + k3 d³`.
    Linear { k: Val, k3: Val },
    /// `f(d) = table(d)`, monotone increasing.
    Table(Table),
}

impl AxisLaw {
    pub fn linear(k: f64) -> AxisLaw {
        AxisLaw::Linear {
            k: Val::lit(k),
            k3: Val::ZERO,
        }
    }

    /// `(f(d), f'(d))`.
    pub fn eval(&self, d: f64) -> (f64, f64) {
        match self {
            AxisLaw::Linear { k, k3 } => (
                k.value * d + k3.value * d * d * d,
                k.value + 3.0 * k3.value * d * d,
            ),
            AxisLaw::Table(t) => t.eval(d),
        }
    }

    /// The stiffness at zero deformation, used by mobility analysis.
    pub fn initial_stiffness(&self) -> f64 {
        self.eval(0.0).1
    }
}
