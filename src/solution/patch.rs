//! What Hessian recovery does the same way in every dimension ([`super::recovery`] on
//! triangles, [`super::recovery3`] on tetrahedra): the vertex adjacency of the cell edges
//! (compressed rows, each row sorted), the vertex patches grown one ring of edges at a
//! time until a fit is determined (the quadratic fit's and the edge fit's of
//! `super::edge_fit`), the least-squares solve of a fit by Householder QR,
//! and the floor under which a recovered Hessian is round-off, and is zeroed.
//!
//! Hand-written QR rather than nalgebra's: the fit runs once per vertex on a small
//! m × C system kept on the stack's shape ([f64; C] rows), and the determinacy test reads
//! the triangular factor's diagonal, which the solve exposes here directly. The tests
//! check it against nalgebra's SVD solve (`recovery3`'s twin).

/// How many units of round-off of the values, over the squared shortest edge, a
/// recovered Hessian may be and still be round-off: a fit amplifies the values' errors
/// by its conditioning (a linear field's Hessian measured at up to 52 units on the
/// tests' meshes, both methods; 20 times that is kept as margin).
pub(super) const ROUNDOFF: f64 = 1e3;

/// The vertex adjacency of `n` vertices along `edges` (each `[a, b]` with a < b, sorted
/// and without repeats): compressed rows, each sorted.
#[derive(Debug, Clone)]
pub(super) struct Adjacency {
    offsets: Vec<u32>,
    neighbours: Vec<u32>,
}

impl Adjacency {
    /// The adjacency of `edges` (sorted, deduplicated, a < b) over `n` vertices.
    pub(super) fn new(n: usize, edges: &[[u32; 2]]) -> Adjacency {
        let mut offsets = vec![0u32; n + 1];
        for &[a, b] in edges {
            offsets[a as usize + 1] += 1;
            offsets[b as usize + 1] += 1;
        }
        for v in 0..n {
            offsets[v + 1] += offsets[v];
        }
        let mut fill = offsets[..n].to_vec();
        let mut neighbours = vec![0u32; offsets[n] as usize];
        for &[a, b] in edges {
            neighbours[fill[a as usize] as usize] = b;
            fill[a as usize] += 1;
            neighbours[fill[b as usize] as usize] = a;
            fill[b as usize] += 1;
        }
        for v in 0..n {
            neighbours[offsets[v] as usize..offsets[v + 1] as usize].sort_unstable();
        }
        Adjacency { offsets, neighbours }
    }

    /// The neighbours of `v`, sorted.
    pub(super) fn of(&self, v: usize) -> &[u32] {
        &self.neighbours[self.offsets[v] as usize..self.offsets[v + 1] as usize]
    }

    /// Whether `v` has a neighbour (some cell uses it).
    pub(super) fn is_used(&self, v: usize) -> bool {
        self.offsets[v + 1] > self.offsets[v]
    }
}

/// Scratch of one thread: a visit stamp per vertex, the last ring and the whole patch.
pub(super) struct Patch {
    stamp: Vec<u32>,
    round: u32,
    ring: Vec<u32>,
    all: Vec<u32>,
    next: Vec<u32>,
}

impl Patch {
    /// Scratch for a mesh of `n` vertices.
    pub(super) fn new(n: usize) -> Patch {
        Patch { stamp: vec![0; n], round: 0, ring: Vec::new(), all: Vec::new(), next: Vec::new() }
    }

    /// The first determined fit at `v`: the patch of the vertices within k edges,
    /// k = 1, 2, … (breadth-first, each ring in the order found), handed to `fit` once it
    /// has at least `min_patch` vertices, until `fit` answers. `Err` with the size of
    /// the largest patch when the connected part of `v` runs out first.
    pub(super) fn grow<R>(
        &mut self,
        adjacency: &Adjacency,
        v: usize,
        min_patch: usize,
        fit: impl FnMut(Grown<'_>) -> Option<R>,
    ) -> Result<R, usize> {
        self.grow_within(adjacency, v, min_patch, usize::MAX, fit)
    }

    /// [`Patch::grow`] that gives up after `max_rings` rings (`Err` with the size of the
    /// last patch), so that the work at a vertex stays bounded whatever the mesh.
    pub(super) fn grow_within<R>(
        &mut self,
        adjacency: &Adjacency,
        v: usize,
        min_patch: usize,
        max_rings: usize,
        mut fit: impl FnMut(Grown<'_>) -> Option<R>,
    ) -> Result<R, usize> {
        self.round = self.round.wrapping_add(1);
        if self.round == 0 {
            self.stamp.iter_mut().for_each(|s| *s = 0);
            self.round = 1;
        }
        let round = self.round;
        self.stamp[v] = round;
        self.ring.clear();
        self.ring.push(v as u32);
        self.all.clear();
        for _ in 0..max_rings {
            self.next.clear();
            for &u in &self.ring {
                for &w in adjacency.of(u as usize) {
                    if self.stamp[w as usize] != round {
                        self.stamp[w as usize] = round;
                        self.next.push(w);
                    }
                }
            }
            if self.next.is_empty() {
                return Err(self.all.len());
            }
            self.all.extend_from_slice(&self.next);
            std::mem::swap(&mut self.ring, &mut self.next);
            if self.all.len() >= min_patch {
                let grown = Grown { others: &self.all, stamp: &self.stamp, round };
                if let Some(r) = fit(grown) {
                    return Ok(r);
                }
            }
        }
        Err(self.all.len())
    }

    /// The fit at `v` on the first patch ([`Patch::grow`]'s, within `max_rings` rings)
    /// whose fit is determined and has a condition number (as `fit` answers it with the
    /// fit) of at most `well`; when none within `max_rings` is, the best conditioned
    /// determined one there; when none is determined there, [`Patch::grow`]'s first
    /// determined fit however far. So a patch grows past the first determined one only
    /// while that one is ill conditioned, and the work stays bounded unless no patch
    /// within `max_rings` is determined at all.
    pub(super) fn grow_conditioned<R>(
        &mut self,
        adjacency: &Adjacency,
        v: usize,
        min_patch: usize,
        max_rings: usize,
        well: f64,
        mut fit: impl FnMut(Grown<'_>) -> Option<(R, f64)>,
    ) -> Result<R, usize> {
        let mut best: Option<(f64, R)> = None;
        let first = self.grow_within(adjacency, v, min_patch, max_rings, |p| {
            let (r, condition) = fit(p)?;
            if condition <= well {
                return Some(r);
            }
            if !best.as_ref().is_some_and(|(c, _)| *c <= condition) {
                best = Some((condition, r));
            }
            None
        });
        match (first, best) {
            (Ok(r), _) => Ok(r),
            (Err(_), Some((_, r))) => Ok(r),
            (Err(_), None) => self.grow(adjacency, v, min_patch, |p| fit(p).map(|(r, _)| r)),
        }
    }
}

/// A patch as [`Patch::grow`] hands it to a fit: its vertices other than the centre, in
/// the order found, and which vertices (the centre included) it holds.
#[derive(Clone, Copy)]
pub(super) struct Grown<'a> {
    /// The vertices within k edges of the centre, the centre left out.
    pub(super) others: &'a [u32],
    stamp: &'a [u32],
    round: u32,
}

impl Grown<'_> {
    /// Whether `w` is the centre or one of `others`.
    pub(super) fn contains(&self, w: u32) -> bool {
        self.stamp[w as usize] == self.round
    }
}

/// The round-off floor of a Hessian at a vertex: a value carries an error of about
/// ε|u|, which a second difference over an edge h turns into ε|u|/h², so a Hessian whose
/// spectral radius is within [`ROUNDOFF`] ε `umax` / `hmin`² (|u| over the vertex and its
/// neighbours, h its shortest edge) says nothing of the field.
fn roundoff_floor(umax: f64, hmin: f64) -> f64 {
    ROUNDOFF * f64::EPSILON * umax / (hmin * hmin)
}

/// Sets to `zero` each Hessian of `hessian` (one per vertex of `points`, whose edges
/// `adjacency` holds) that is round-off: whose bound `radius` on its spectral radius is
/// within its vertex's [`roundoff_floor`]. A linear field's Hessian is then zero at every
/// vertex and asks for nothing (it gave an anisotropy of 167 from noise); a quadratic's
/// is far above the floor. A vertex that no cell uses, or whose edges all have zero
/// length, keeps its Hessian.
pub(super) fn drop_roundoff<const D: usize, H>(
    points: &[[f64; D]],
    adjacency: &Adjacency,
    values: &[f64],
    hessian: &mut [H],
    radius: impl Fn(&H) -> f64,
    zero: H,
) where
    H: Copy,
{
    for (v, h) in hessian.iter_mut().enumerate() {
        if !adjacency.is_used(v) {
            continue;
        }
        let p = points[v];
        let (mut umax, mut hmin) = (values[v].abs(), f64::INFINITY);
        for &w in adjacency.of(v) {
            let q = points[w as usize];
            umax = umax.max(values[w as usize].abs());
            // hypot pair by pair, x and y first: the length the plane and space took.
            let len = (2..D).fold((q[0] - p[0]).hypot(q[1] - p[1]), |l, k| l.hypot(q[k] - p[k]));
            if len > 0.0 {
                hmin = hmin.min(len);
            }
        }
        if hmin.is_finite() && radius(h) <= roundoff_floor(umax, hmin) {
            *h = zero;
        }
    }
}

/// The least-squares solution of `a x = b` (a: m × C, m ≥ C) by Householder QR;
/// `None` when the triangular factor's smallest diagonal entry is below `determined`
/// times its largest. Overwrites `a` and `b`.
pub(super) fn least_squares<const C: usize>(
    a: &mut [[f64; C]],
    b: &mut [f64],
    determined: f64,
) -> Option<[f64; C]> {
    least_squares_conditioned(a, b, determined).map(|(x, _)| x)
}

/// [`least_squares`] with the condition number of `a` in the Frobenius norm,
/// ‖R‖ ‖R⁻¹‖ of its triangular factor R (an upper bound of the 2-norm's, within a
/// factor C): how much the fit may amplify the part of `b` it cannot fit.
pub(super) fn least_squares_conditioned<const C: usize>(
    a: &mut [[f64; C]],
    b: &mut [f64],
    determined: f64,
) -> Option<([f64; C], f64)> {
    let m = a.len();
    if m < C {
        return None;
    }
    let mut diag = [0.0; C];
    for k in 0..C {
        let norm = (k..m).map(|i| a[i][k] * a[i][k]).sum::<f64>().sqrt();
        if norm == 0.0 {
            return None;
        }
        let alpha = if a[k][k] > 0.0 { -norm } else { norm };
        // v = a[k..][k] - alpha e1, stored in place.
        a[k][k] -= alpha;
        let vnorm2: f64 = (k..m).map(|i| a[i][k] * a[i][k]).sum();
        if vnorm2 > 0.0 {
            for j in k + 1..C {
                let dot: f64 = (k..m).map(|i| a[i][k] * a[i][j]).sum();
                let f = 2.0 * dot / vnorm2;
                for row in &mut a[k..] {
                    row[j] -= f * row[k];
                }
            }
            let dot: f64 = (k..m).map(|i| a[i][k] * b[i]).sum();
            let f = 2.0 * dot / vnorm2;
            for i in k..m {
                b[i] -= f * a[i][k];
            }
        }
        diag[k] = alpha;
    }
    let largest = diag.iter().fold(0.0f64, |x, d| x.max(d.abs()));
    if diag.iter().any(|d| d.abs() < determined * largest || d.is_nan()) {
        return None;
    }
    let mut x = [0.0; C];
    for k in (0..C).rev() {
        let s: f64 = (k + 1..C).map(|j| a[k][j] * x[j]).sum();
        x[k] = (b[k] - s) / diag[k];
    }
    Some((x, condition(a, &diag)))
}

/// ‖R‖_F ‖R⁻¹‖_F of the triangular factor whose diagonal is `diag` and whose strict
/// upper part is that of `a`'s first C rows; R⁻¹ by back substitution, column by column.
fn condition<const C: usize>(a: &[[f64; C]], diag: &[f64; C]) -> f64 {
    let r = |i: usize, j: usize| if i == j { diag[i] } else { a[i][j] };
    let mut norm = 0.0;
    let mut inverse = 0.0;
    for j in 0..C {
        // Column j of R⁻¹: R y = e_j, y zero below row j.
        let mut y = [0.0; C];
        for i in (0..=j).rev() {
            let s: f64 = (i + 1..=j).map(|k| r(i, k) * y[k]).sum();
            y[i] = (if i == j { 1.0 } else { 0.0 } - s) / diag[i];
        }
        inverse += y.iter().map(|x| x * x).sum::<f64>();
        norm += (0..=j).map(|i| r(i, j) * r(i, j)).sum::<f64>();
    }
    (norm * inverse).sqrt()
}
