//! The broad phase's search: the pairs of elements of two bodies (or of
//! one with itself) within their margins and the reach of each other at
//! their anchors, through a uniform grid over the elements' boxes.

use std::cell::Cell;

use super::elements::{distance, Elements, Kind};
use crate::contact::grid::Grid;
use crate::units::{Real, Vec3};

/// Most cells one element's box spans along an axis in the grid of a
/// search (the grid's own cap is 16).
const CELLS_PER_BOX: Real = 15.0;

/// Most pairs of elements searched each with each, without a grid.
const DIRECT_PAIRS: usize = 256;

/// What a search reads: the elements, their boxes about the anchors
/// grown by their bodies' margins and their reach (m), where the
/// particles were at the anchors (m), and the reach (m) of surface pairs
/// (the gap) and of two loose particles (twice the radius).
pub(super) struct Anchored<'a> {
    pub elements: &'a Elements,
    pub boxes: &'a [(Vec3, Vec3)],
    pub anchor: &'a [Vec3],
    pub reach: (Real, Real),
}

impl Anchored<'_> {
    /// Call `visit(p, q, d)` on each pair of elements of spans `a` and `b`
    /// (the same: of one body with itself) whose distance `d` (m) at the
    /// anchors is within `within` (m, the two margins) and their reach of
    /// each other, in a fixed order: `b`'s element boxes in `grid`, each of
    /// `a`'s looked up in it (or, for at most `DIRECT_PAIRS` pairs, each
    /// of `a`'s with each of `b`'s in their order). `visit` returns `false` to end the search:
    /// then so does this; `true` when every pair was visited.
    pub fn each_pair(
        &self,
        grid: &mut Grid,
        (a, b): (usize, usize),
        within: Real,
        mut visit: impl FnMut(u32, u32, Real) -> bool,
    ) -> bool {
        let elements = self.elements;
        let (sa, sb) = (elements.spans[a].clone(), elements.spans[b].clone());
        let boxes = self.boxes;
        let extent = |e: usize| {
            let (lo, hi) = boxes[e];
            (hi - lo).max_element()
        };
        let widest = sa
            .clone()
            .chain(sb.clone())
            .map(extent)
            .fold(0.0, Real::max);
        let mean = sb.clone().map(extent).sum::<Real>() / sb.len().max(1) as Real;
        let cell = mean.max(widest / CELLS_PER_BOX);
        if !(cell > 0.0 && cell.is_finite()) {
            return true;
        }
        let (gap, balls) = self.reach;
        // Visit the pair of elements `e` (of `a`) and `f` (of `b`), whose
        // boxes overlap: whether the search goes on.
        let mut meet = |e: usize, f: usize| -> bool {
            let Some((p, q)) = elements.pair(e, f) else {
                return true;
            };
            let (ep, eq) = (&elements.list[p], &elements.list[q]);
            let reach = if ep.kind == Kind::Point(true) && eq.kind == Kind::Point(true) {
                balls
            } else {
                gap
            };
            let d = distance(ep, eq, self.anchor);
            d > within + reach || visit(p as u32, q as u32, d)
        };
        let overlap = |e: usize, f: usize| {
            let ((lo, hi), (flo, fhi)) = (boxes[e], boxes[f]);
            lo.cmple(fhi).all() && flo.cmple(hi).all()
        };
        // Few pairs (small bodies, as ropes of a few particles stacked by
        // the thousand): each with each, cheaper than building a grid.
        if sa.len() * sb.len() <= DIRECT_PAIRS {
            for e in sa {
                let from = if a == b { e + 1 } else { sb.start };
                for f in from..sb.end {
                    if overlap(e, f) && !meet(e, f) {
                        return false;
                    }
                }
            }
            return true;
        }
        grid.build(cell, sb.clone().map(|e| boxes[e]));
        let first = sb.start;
        let going = Cell::new(true);
        for e in sa {
            let (lo, hi) = boxes[e];
            let skip = if a == b { e - sb.start + 1 } else { 0 };
            grid.query_once(
                lo,
                hi,
                |f| going.get() && f as usize >= skip,
                |f| {
                    let f = first + f as usize;
                    if overlap(e, f) {
                        going.set(meet(e, f));
                    }
                },
            );
            if !going.get() {
                return false;
            }
        }
        true
    }

    /// The pairs [`Anchored::each_pair`] visits, nearest first (ties by
    /// the elements), if there are at most `most` of them; `None` if
    /// there are more (and at most `most` were ever held).
    pub fn pairs(
        &self,
        grid: &mut Grid,
        spans: (usize, usize),
        within: Real,
        most: usize,
    ) -> Option<Vec<(u32, u32, Real)>> {
        let mut pairs = Vec::new();
        let all = self.each_pair(grid, spans, within, |p, q, d| {
            if pairs.len() == most {
                return false;
            }
            pairs.push((p, q, d));
            true
        });
        if !all {
            return None;
        }
        pairs.shrink_to_fit();
        pairs.sort_by(|x, y| x.2.total_cmp(&y.2).then((x.0, x.1).cmp(&(y.0, y.1))));
        Some(pairs)
    }
}
