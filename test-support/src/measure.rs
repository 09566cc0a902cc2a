//! Measures of a triangle, written apart from the library's own so that a test checks
//! the library's output with figures it did not compute itself: the signed area, the
//! smallest angle (law of cosines), the shape quality 4√3·A / (l₁² + l₂² + l₃²), and the
//! distance from a point to a segment.

use crate::grid::Point2;

/// Twice the signed area of `(a, b, c)`, as a cross product: positive when the corners
/// run counter-clockwise.
fn cross(a: Point2, b: Point2, c: Point2) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
}

/// Signed area of triangle `(a, b, c)`: positive when counter-clockwise.
pub fn signed_area(a: Point2, b: Point2, c: Point2) -> f64 {
    cross(a, b, c) / 2.0
}

/// The smallest interior angle of a triangle, in degrees, from its side lengths (the
/// smallest angle faces the shortest side); 0 for a degenerate one.
pub fn min_angle_deg(a: Point2, b: Point2, c: Point2) -> f64 {
    let len = |p: Point2, q: Point2| (p[0] - q[0]).hypot(p[1] - q[1]);
    let mut s = [len(b, c), len(c, a), len(a, b)];
    s.sort_by(f64::total_cmp);
    let [short, m, long] = s;
    if short == 0.0 {
        return 0.0;
    }
    let cos = ((m * m + long * long - short * short) / (2.0 * m * long)).clamp(-1.0, 1.0);
    cos.acos().to_degrees()
}

/// Shape quality in [0, 1]: 1 for an equilateral triangle, 0 for a degenerate one,
/// negative for a clockwise one.
pub fn quality(a: Point2, b: Point2, c: Point2) -> f64 {
    let sq = |p: Point2, q: Point2| (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]);
    let sum = sq(a, b) + sq(b, c) + sq(c, a);
    if sum == 0.0 {
        0.0
    } else {
        2.0 * 3f64.sqrt() * cross(a, b, c) / sum
    }
}

/// The distance from `p` to segment `[a, b]` (to `a` when the segment is a point): the
/// foot at the clamped parameter of the orthogonal projection.
pub fn distance_to_segment(p: Point2, a: Point2, b: Point2) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] - (a[0] + t * d[0])).hypot(p[1] - (a[1] + t * d[1]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn measures_by_hand() {
        let h = 3f64.sqrt() / 2.0;
        let (a, b, c) = ([0.0, 0.0], [1.0, 0.0], [0.5, h]);
        assert!((signed_area(a, b, c) - h / 2.0).abs() < 1e-15);
        assert!((signed_area(a, c, b) + h / 2.0).abs() < 1e-15);
        assert!((min_angle_deg(a, b, c) - 60.0).abs() < 1e-9);
        assert!((quality(a, b, c) - 1.0).abs() < 1e-15);
        // The right isosceles triangle: 45 degrees; quality 4√3·(1/2) / 4 = √3/2.
        let (a, b, c) = ([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]);
        assert!((min_angle_deg(a, b, c) - 45.0).abs() < 1e-9);
        assert!((quality(a, b, c) - 3f64.sqrt() / 2.0).abs() < 1e-15);
        assert_eq!(min_angle_deg(a, a, c), 0.0);
        assert_eq!(quality(a, a, a), 0.0);
        assert_eq!(distance_to_segment([0.5, 2.0], [0.0, 0.0], [1.0, 0.0]), 2.0);
        assert_eq!(distance_to_segment([4.0, 4.0], [0.0, 0.0], [1.0, 0.0]), 5.0);
        assert_eq!(distance_to_segment([3.0, 4.0], [0.0, 0.0], [0.0, 0.0]), 5.0);
    }
}
