//! Rectangles and the map from mesh coordinates to picture pixels: uniform scale
//! (so that circles stay circles and ellipses keep their axes), y pointing up in the
//! mesh and down in the picture, the world rectangle centred in the pixel one.

/// An axis-aligned rectangle `[x0, x1] × [y0, y1]`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Rect {
    /// Smallest x.
    pub x0: f64,
    /// Smallest y.
    pub y0: f64,
    /// Largest x.
    pub x1: f64,
    /// Largest y.
    pub y1: f64,
}

impl Rect {
    /// The rectangle of corners `(x0, y0)` and `(x1, y1)`.
    pub fn new(x0: f64, y0: f64, x1: f64, y1: f64) -> Rect {
        Rect { x0: x0.min(x1), y0: y0.min(y1), x1: x0.max(x1), y1: y0.max(y1) }
    }

    /// The bounding box of `points`, `None` when there is none.
    pub fn bounding(points: impl IntoIterator<Item = [f64; 2]>) -> Option<Rect> {
        let mut r: Option<Rect> = None;
        for p in points {
            r = Some(match r {
                None => Rect { x0: p[0], y0: p[1], x1: p[0], y1: p[1] },
                Some(r) => Rect {
                    x0: r.x0.min(p[0]),
                    y0: r.y0.min(p[1]),
                    x1: r.x1.max(p[0]),
                    y1: r.y1.max(p[1]),
                },
            });
        }
        r
    }

    /// Width.
    pub fn width(&self) -> f64 {
        self.x1 - self.x0
    }

    /// Height.
    pub fn height(&self) -> f64 {
        self.y1 - self.y0
    }

    /// Centre.
    pub fn centre(&self) -> [f64; 2] {
        [0.5 * (self.x0 + self.x1), 0.5 * (self.y0 + self.y1)]
    }

    /// Length of the diagonal.
    pub fn diagonal(&self) -> f64 {
        self.width().hypot(self.height())
    }

    /// Grown by `m` on every side.
    pub fn inflate(&self, m: f64) -> Rect {
        Rect { x0: self.x0 - m, y0: self.y0 - m, x1: self.x1 + m, y1: self.y1 + m }
    }

    /// The common part of two rectangles, `None` when they do not overlap.
    pub fn intersect(&self, o: &Rect) -> Option<Rect> {
        let r = Rect {
            x0: self.x0.max(o.x0),
            y0: self.y0.max(o.y0),
            x1: self.x1.min(o.x1),
            y1: self.y1.min(o.y1),
        };
        (r.x0 <= r.x1 && r.y0 <= r.y1).then_some(r)
    }

    /// Whether `p` lies inside or on the border.
    pub fn contains(&self, p: [f64; 2]) -> bool {
        (self.x0..=self.x1).contains(&p[0]) && (self.y0..=self.y1).contains(&p[1])
    }

    /// Moved (not resized) to lie inside `outer` along each axis where it fits, and
    /// centred on `outer` along an axis where it is larger.
    pub fn shift_inside(&self, outer: &Rect) -> Rect {
        let shift = |lo: f64, hi: f64, olo: f64, ohi: f64| {
            if hi - lo >= ohi - olo {
                0.5 * (olo + ohi) - 0.5 * (lo + hi)
            } else if lo < olo {
                olo - lo
            } else if hi > ohi {
                ohi - hi
            } else {
                0.0
            }
        };
        let dx = shift(self.x0, self.x1, outer.x0, outer.x1);
        let dy = shift(self.y0, self.y1, outer.y0, outer.y1);
        Rect { x0: self.x0 + dx, y0: self.y0 + dy, x1: self.x1 + dx, y1: self.y1 + dy }
    }

    /// Grown around its centre along one axis until width / height equals `aspect`.
    pub fn with_aspect(&self, aspect: f64) -> Rect {
        let [cx, cy] = self.centre();
        let (mut w, mut h) = (self.width().max(1e-300), self.height().max(1e-300));
        if w / h < aspect {
            w = h * aspect;
        } else {
            h = w / aspect;
        }
        Rect { x0: cx - 0.5 * w, y0: cy - 0.5 * h, x1: cx + 0.5 * w, y1: cy + 0.5 * h }
    }
}

/// Mesh coordinates to pixels: `px = origin + scale · (p − world corner)`, y flipped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct View {
    /// The part of the plane shown (grown to the pixel rectangle's aspect).
    pub world: Rect,
    /// Where it is drawn, in pixels (y down).
    pub screen: Rect,
    /// Pixels per mesh unit.
    pub scale: f64,
}

impl View {
    /// Fits `world` into `screen`, keeping its aspect and centring it.
    pub(super) fn fit(world: Rect, screen: Rect) -> View {
        let w = world.width().max(1e-300);
        let h = world.height().max(1e-300);
        let scale = (screen.width() / w).min(screen.height() / h);
        let shown = world.with_aspect(screen.width() / screen.height());
        View { world: shown, screen, scale }
    }

    /// The pixel position of mesh point `p`.
    #[inline]
    pub(super) fn to_px(self, p: [f64; 2]) -> [f64; 2] {
        let [cx, cy] = self.world.centre();
        let [sx, sy] = self.screen.centre();
        [sx + self.scale * (p[0] - cx), sy - self.scale * (p[1] - cy)]
    }

    /// The pixel rectangle of a mesh rectangle.
    pub(super) fn rect_to_px(&self, r: &Rect) -> Rect {
        let a = self.to_px([r.x0, r.y0]);
        let b = self.to_px([r.x1, r.y1]);
        Rect::new(a[0], a[1], b[0], b[1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_keeps_aspect_and_flips_y() {
        let v = View::fit(Rect::new(0.0, 0.0, 4.0, 1.0), Rect::new(10.0, 10.0, 410.0, 210.0));
        assert_eq!(v.scale, 100.0);
        assert_eq!(v.to_px([0.0, 0.0]), [10.0, 160.0]);
        assert_eq!(v.to_px([4.0, 1.0]), [410.0, 60.0]);
        assert_eq!(v.world.height(), 2.0);
    }

    #[test]
    fn shifting_inside_moves_without_resizing() {
        let outer = Rect::new(0.0, 0.0, 4.0, 1.0);
        let r = Rect::new(-0.5, 0.2, 0.5, 0.6).shift_inside(&outer);
        assert_eq!((r.x0, r.x1, r.y0, r.y1), (0.0, 1.0, 0.2, 0.6));
        let r = Rect::new(3.0, -1.0, 5.0, 2.0).shift_inside(&outer);
        assert_eq!((r.x0, r.x1, r.y0, r.y1), (2.0, 4.0, -1.0, 2.0));
    }

    #[test]
    fn aspect_grows_the_short_side() {
        let r = Rect::new(0.0, 0.0, 1.0, 1.0).with_aspect(2.0);
        assert_eq!((r.x0, r.x1, r.y0, r.y1), (-0.5, 1.5, 0.0, 1.0));
    }
}
