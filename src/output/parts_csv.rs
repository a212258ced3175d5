//! `solve --format csv` for a model without wheels: one row per case and
//! moving part, the part frame's position and rotation vector.

use super::number::csv as num;
use crate::geom::Mat3;
use crate::output::report::CaseReport;

pub const COLUMNS: &str = "step,loadcase,part,x,y,z,rx_deg,ry_deg,rz_deg";

/// Position (mm, global) and rotation vector (axis times angle, deg, global) per part.
pub fn csv(cases: &[CaseReport]) -> String {
    let mut out = format!("{COLUMNS}\n");
    for c in cases {
        for (name, p) in &c.parts {
            let r = Mat3::from_fn(|i, j| p.rotation[i][j]);
            let rv = nalgebra::Rotation3::from_matrix_unchecked(r)
                .scaled_axis()
                .map(f64::to_degrees);
            let nums = [
                p.position[0],
                p.position[1],
                p.position[2],
                rv.x,
                rv.y,
                rv.z,
            ]
            .map(num);
            out += &format!("{},{},{name},{}\n", c.step, c.name, nums.join(","));
        }
    }
    out
}
