//! "Did you mean" candidates by edit distance.

/// Edit distance between two strings (by characters): insertions, deletions,
/// substitutions and swaps of two neighbouring characters (`amr` → `arm` is one
/// edit, the commonest typing slip), i.e. the optimal string alignment distance.
pub fn distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    // d[i][j]: distance between the first i characters of a and the first j of b.
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    for (j, v) in d[0].iter_mut().enumerate() {
        *v = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut v = (d[i - 1][j - 1] + cost)
                .min(d[i - 1][j] + 1)
                .min(d[i][j - 1] + 1);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                v = v.min(d[i - 2][j - 2] + 1);
            }
            d[i][j] = v;
        }
    }
    d[a.len()][b.len()]
}

/// The closest candidate within a third of the name's length (at least 1 edit,
/// at most 3), or one that differs only by case.
pub fn best<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let limit = (name.chars().count() / 3).clamp(1, 3);
    candidates
        .into_iter()
        .map(|c| {
            let d = if c.eq_ignore_ascii_case(name) {
                0
            } else {
                distance(name, c)
            };
            (d, c)
        })
        .filter(|(d, _)| *d <= limit)
        .min_by_key(|(d, c)| (*d, *c))
        .map(|(_, c)| c)
}

/// `did you mean `x`?` or an empty hint.
pub fn did_you_mean<'a>(
    name: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<String> {
    best(name, candidates).map(did_you_mean_text)
}

/// The wording of a suggestion, once.
pub fn did_you_mean_text(candidate: &str) -> String {
    format!("did you mean `{candidate}`?")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_near_names() {
        assert_eq!(distance("kitten", "sitting"), 3);
        assert_eq!(best("uprigth", ["upright", "chassis"]), Some("upright"));
        assert_eq!(
            best("front_arm", ["rear_arm", "front_arm2"]),
            Some("front_arm2")
        );
        assert_eq!(best("zzz", ["upright"]), None);
        assert_eq!(best("Chassis", ["chassis"]), Some("chassis"));
        // A swap of two neighbours is one edit, not two.
        assert_eq!(distance("amr", "arm"), 1);
        assert_eq!(distance("uprigth", "upright"), 1);
        assert_eq!(best("amr", ["arm", "chassis"]), Some("arm"));
        assert_eq!(distance("", "abc"), 3);
        assert_eq!(distance("ab", "ba"), 1);
    }
}
