//! The nearest valid name to a misspelt one (“did you mean …?”).
//!
//! Optimal-string-alignment distance (Levenshtein plus transpositions, so `Prep` is one
//! edit from `Perp`), compared without regard to case, as `MinSize` and `MINSIZE` are
//! the same mistake as far as a reader is concerned.

/// The candidate closest to `word`, when it is close enough to be a plausible typo:
/// about a third of the word's length in edits (at least 1, at most 3). Ties go to
/// the first candidate, so the answer does not depend on anything but the order given.
pub fn nearest<'a, I>(word: &str, candidates: I) -> Option<&'a str>
where
    I: IntoIterator<Item = &'a str>,
{
    let w = word.to_lowercase();
    let limit = ((w.chars().count() + 1) / 3).clamp(1, 3);
    // Ranked by the distance without case, then with case (so `distance_to_boarder`
    // prefers `distance_to_border` to `DISTANCE_TO_BORDER`), then by order.
    let mut best: Option<((usize, usize), &'a str)> = None;
    for c in candidates {
        if c == word {
            continue;
        }
        let d = strsim::osa_distance(&w, &c.to_lowercase());
        if d > limit {
            continue;
        }
        let rank = (d, strsim::osa_distance(word, c));
        if best.map_or(true, |(b, _)| rank < b) {
            best = Some((rank, c));
        }
    }
    best.map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    use super::nearest;

    #[test]
    fn typos_find_their_word() {
        let keys = ["MINSIZE", "MAXSIZE", "MAXDISTANCE", "EXPONENT"];
        assert_eq!(nearest("MINSIZ", keys), Some("MINSIZE"));
        assert_eq!(nearest("minsize", keys), Some("MINSIZE"));
        assert_eq!(nearest("MAXDISTNACE", keys), Some("MAXDISTANCE"));
        assert_eq!(
            nearest("FStayVanePrep", ["FStayVanePara", "FStayVanePerp"]),
            Some("FStayVanePerp")
        );
        assert_eq!(nearest("COLOUR", keys), None);
        assert_eq!(nearest("X", ["Y"]), Some("Y"));
        assert_eq!(nearest("X", ["YZ"]), None);
    }
}
