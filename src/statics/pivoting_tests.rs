//! Tests of the choice of pivots that do not need a mechanism.

use super::*;

/// The Markowitz choice on a small active submatrix: the entry of least
/// cost `(r - 1)(c - 1)` among those that pass the threshold in their
/// column, ties to the larger entry against its column's largest; an entry
/// under the threshold is passed over whatever its cost; and an active row
/// left empty (as in a singular matrix) is passed over, without an
/// underflow of its count.
#[test]
fn the_markowitz_pivot_is_the_cheapest_entry_that_passes_the_threshold() {
    // Column 0 holds rows 0 and 1 (cost 1 each), column 1 rows 0 to 2
    // (cost 2 for rows 0 and 1). Row 2's lone entry costs 0 but is under
    // 0.1 of its column's largest (4): the pivot is in column 0, row 1's
    // entry (all of its column's largest) rather than row 0's (a third).
    let mut rows = vec![
        vec![(0, 1.0), (1, 4.0)],
        vec![(0, -3.0), (1, 1.0)],
        vec![(1, 0.2)],
        vec![],
    ];
    let count = [2, 3];
    let mut max = [0.0; 2];
    let pivoted = [false; 4];
    let pick = |rows: &[Vec<(usize, f64)>], pivoted: &[bool], max: &mut [f64]| {
        markowitz_pivot(rows, pivoted, &count, max)
    };
    assert_eq!(pick(&rows, &pivoted, &mut max), Some((1, 0)));
    // At half of its column's largest, row 2's lone entry is the pivot.
    rows[2] = vec![(1, 2.0)];
    assert_eq!(pick(&rows, &pivoted, &mut max), Some((2, 1)));
    // Nothing left but the empty row: no pivot.
    assert_eq!(pick(&rows, &[true, true, true, false], &mut max), None);
}
