//! "Did you mean": the known name nearest to a misspelled one.

/// The candidate nearest to `name`: fewest edits (case counts half), or, for a name that
/// lengthens a known one (`MoveAbsolute`), the longest such; `None` if nothing is near.
pub fn nearest<'a>(name: &str, candidates: impl Iterator<Item = &'a str>) -> Option<&'a str> {
    let mut best: Option<(usize, &'a str)> = None;
    let mut prefix: Option<&'a str> = None;
    let lower = name.to_ascii_lowercase();
    for candidate in candidates {
        let folded = distance(&lower, &candidate.to_ascii_lowercase());
        let cost = folded * 2 + usize::from(distance(name, candidate) > folded);
        let allowed = 2 * (name.len() / 4).clamp(1, 3) + 1;
        if cost <= allowed && best.is_none_or(|(b, c)| (cost, candidate) < (b, c)) {
            best = Some((cost, candidate));
        }
        let lengthens = candidate.len() >= 4 && lower.starts_with(&candidate.to_ascii_lowercase());
        if lengthens && prefix.is_none_or(|p| candidate.len() > p.len()) {
            prefix = Some(candidate);
        }
    }
    best.map(|(_, c)| c).or(prefix)
}

/// Edits (insert, delete, replace, swap of neighbours) from `a` to `b`.
fn distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let mut rows = vec![vec![0; b.len() + 1]; a.len() + 1];
    for (i, row) in rows.iter_mut().enumerate() {
        row[0] = i;
    }
    for (j, cell) in rows[0].iter_mut().enumerate() {
        *cell = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let replace = rows[i - 1][j - 1] + usize::from(a[i - 1] != b[j - 1]);
            let mut d = replace.min(rows[i - 1][j] + 1).min(rows[i][j - 1] + 1);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                d = d.min(rows[i - 2][j - 2] + 1);
            }
            rows[i][j] = d;
        }
    }
    rows[a.len()][b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn near_names() {
        let known = ["MoveAbs", "MoveRel", "BM_LOOKAHEAD", "BM_BUFF", "Enable", "IsInPos"];
        for (typed, meant) in [
            ("MoveAbsolute", Some("MoveAbs")),
            ("BM_LOOKAHAED", Some("BM_LOOKAHEAD")),
            ("moveabs", Some("MoveAbs")),
            ("Enabel", Some("Enable")),
            ("IsInPosition", Some("IsInPos")),
            ("Frobnicate", None),
        ] {
            assert_eq!(nearest(typed, known.into_iter()), meant, "{typed}");
        }
    }
}
