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

/// The three laws of one bushing family (forces along, or torques about, the
/// x, y, z axes of J). An axisymmetric family stores its radial law once, so
/// that x and y cannot disagree: the only way to change one is to change both.
#[derive(Debug, Clone, PartialEq)]
pub enum AxisLaws {
    /// Three independent laws.
    General([AxisLaw; 3]),
    /// x and y share `radial` (written `k_radial`/`kt_radial`); z is the axis.
    Axisymmetric { radial: AxisLaw, axial: AxisLaw },
}

impl AxisLaws {
    /// Three laws, kept axisymmetric when x and y are equal and `symmetric` asks for it.
    pub fn from_three(laws: [AxisLaw; 3], symmetric: bool) -> AxisLaws {
        let [x, y, z] = laws;
        if symmetric && x == y {
            AxisLaws::Axisymmetric {
                radial: x,
                axial: z,
            }
        } else {
            AxisLaws::General([x, y, z])
        }
    }

    pub fn is_axisymmetric(&self) -> bool {
        matches!(self, AxisLaws::Axisymmetric { .. })
    }

    /// The axis whose storage `axis` shares (y reads x's radial law).
    pub fn stored_axis(&self, axis: usize) -> usize {
        match self {
            AxisLaws::Axisymmetric { .. } if axis == 1 => 0,
            _ => axis,
        }
    }

    /// The law along axis 0, 1 or 2 (x and y of an axisymmetric family are one law).
    pub fn get(&self, axis: usize) -> &AxisLaw {
        match self {
            AxisLaws::General(l) => &l[axis],
            AxisLaws::Axisymmetric { radial, axial } => {
                if axis == 2 {
                    axial
                } else {
                    radial
                }
            }
        }
    }

    /// The law along `axis`, for changing it; on an axisymmetric family x and y
    /// are one law, so changing either changes both.
    pub fn get_mut(&mut self, axis: usize) -> &mut AxisLaw {
        match self {
            AxisLaws::General(l) => &mut l[axis],
            AxisLaws::Axisymmetric { radial, axial } => {
                if axis == 2 {
                    axial
                } else {
                    radial
                }
            }
        }
    }

    /// The laws along x, y, z (an axisymmetric radial law twice).
    pub fn iter(&self) -> impl Iterator<Item = &AxisLaw> + '_ {
        (0..3).map(|a| self.get(a))
    }

    /// Each stored law once (the radial law of an axisymmetric family once).
    pub fn stored_mut(&mut self) -> Vec<&mut AxisLaw> {
        match self {
            AxisLaws::General(l) => l.iter_mut().collect(),
            AxisLaws::Axisymmetric { radial, axial } => vec![radial, axial],
        }
    }

    /// The three laws as independent copies.
    pub fn to_three(&self) -> [AxisLaw; 3] {
        std::array::from_fn(|a| self.get(a).clone())
    }
}

impl std::ops::Index<usize> for AxisLaws {
    type Output = AxisLaw;
    fn index(&self, axis: usize) -> &AxisLaw {
        self.get(axis)
    }
}

impl<'a> IntoIterator for &'a AxisLaws {
    type Item = &'a AxisLaw;
    type IntoIter = std::iter::Map<std::ops::Range<usize>, Box<dyn Fn(usize) -> &'a AxisLaw + 'a>>;
    fn into_iter(self) -> Self::IntoIter {
        (0..3).map(Box::new(move |a| self.get(a)))
    }
}

/// `laws[axis] = ...`: on an axisymmetric family x and y are one law, so
/// changing either changes both (see [`AxisLaws::get_mut`]).
impl std::ops::IndexMut<usize> for AxisLaws {
    fn index_mut(&mut self, axis: usize) -> &mut AxisLaw {
        self.get_mut(axis)
    }
}
