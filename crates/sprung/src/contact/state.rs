//! The part of the contact stage that lives from step to step, for
//! checkpoints: the candidate pairs of the last search (kept while the
//! search margin covers the motion), the positions they were searched from
//! and the margin. A resumed run has the same pairs, so it goes on with
//! the same bits while bodies touch.

use super::buckets::CLEARANCE_BUCKETS;
use super::detect::Scratch;
use super::pairs::{beyond, Spare};
use super::{Contacts, EdgeEdge, PointPoint, PointSegment, PointTriangle};
use crate::body::Body;
use crate::state::{StateError, WorldState};
use crate::units::{Real, Vec3};

impl Contacts {
    /// Add the last search and its pairs to `state`.
    pub fn save_state(&self, state: &mut WorldState) {
        let (margin, at) = self.scratch.last_search();
        state.put(
            "contact.search",
            margin.map(|m| vec![m]).unwrap_or_default(),
        );
        state.put_vectors("contact.searched_at", at);
        let index = |i: u32| Real::from(i);
        let pairs = &self.pairs;
        state.put(
            "contact.point_triangle",
            pairs
                .point_triangle
                .iter()
                .flat_map(|p| {
                    let [a, b, c] = p.element.map(index);
                    [index(p.particle), a, b, c, index(p.body), p.side]
                })
                .collect(),
        );
        state.put(
            "contact.point_segment",
            pairs
                .point_segment
                .iter()
                .flat_map(|p| {
                    let [a, b] = p.element.map(index);
                    [index(p.particle), a, b, index(p.body), p.side]
                })
                .collect(),
        );
        state.put(
            "contact.edge_edge",
            pairs
                .edge_edge
                .iter()
                .flat_map(|p| {
                    let [a, b] = p.first.map(index);
                    let [c, d] = p.second.map(index);
                    let n = p.direction;
                    [a, b, c, d, n.x, n.y, n.z]
                })
                .collect(),
        );
        state.put(
            "contact.point_point",
            pairs
                .point_point
                .iter()
                .flat_map(|p| {
                    let n = p.direction;
                    [index(p.first), index(p.second), n.x, n.y, n.z]
                })
                .collect(),
        );
    }

    /// Take back what [`Contacts::save_state`] saved, for `bodies` over
    /// `particles` particles; refused (and nothing changed) when an index
    /// is out of range or an entry is malformed.
    pub fn restore_state(
        &mut self,
        state: &WorldState,
        bodies: &[Body],
        particles: usize,
    ) -> Result<(), StateError> {
        let search = state.get_any("contact.search")?;
        let margin = match search {
            [] => None,
            [m] => Some(*m),
            _ => return Err(bad("contact.search", 1, search[1])),
        };
        let at = match margin {
            Some(_) => state.get_vectors("contact.searched_at", particles)?,
            None => state.get_vectors("contact.searched_at", 0)?,
        };
        let rows = |name: &'static str, width: usize| -> Result<Vec<&[Real]>, StateError> {
            let values = state.get_any(name)?;
            if values.len() % width != 0 {
                return Err(StateError::Length {
                    name: name.into(),
                    expected: values.len() - values.len() % width,
                    found: values.len(),
                });
            }
            Ok(values.chunks_exact(width).collect())
        };
        // An index below `limit`, at column `k` of entry `name`.
        let index = |name: &str, row: &[Real], k: usize, limit: usize| {
            let v = row[k];
            if v >= 0.0 && v.fract() == 0.0 && v < limit as Real {
                Ok(v as u32)
            } else {
                Err(bad(name, k, v))
            }
        };
        let n = particles;
        let mut pairs = super::ContactPairs::default();
        for r in rows("contact.point_triangle", 6)? {
            let i = |k| index("contact.point_triangle", r, k, n);
            pairs.point_triangle.push(PointTriangle {
                particle: i(0)?,
                element: [i(1)?, i(2)?, i(3)?],
                body: index("contact.point_triangle", r, 4, bodies.len())?,
                side: r[5],
                clearance: 0.0,
            });
        }
        for r in rows("contact.point_segment", 5)? {
            let i = |k| index("contact.point_segment", r, k, n);
            pairs.point_segment.push(PointSegment {
                particle: i(0)?,
                element: [i(1)?, i(2)?],
                body: index("contact.point_segment", r, 3, bodies.len())?,
                side: r[4],
                clearance: 0.0,
            });
        }
        for r in rows("contact.edge_edge", 7)? {
            let i = |k| index("contact.edge_edge", r, k, n);
            pairs.edge_edge.push(EdgeEdge {
                first: [i(0)?, i(1)?],
                second: [i(2)?, i(3)?],
                direction: Vec3::new(r[4], r[5], r[6]),
                clearance: 0.0,
            });
        }
        for r in rows("contact.point_point", 5)? {
            let i = |k| index("contact.point_point", r, k, n);
            pairs.point_point.push(PointPoint {
                first: i(0)?,
                second: i(1)?,
                direction: Vec3::new(r[2], r[3], r[4]),
                clearance: 0.0,
            });
        }
        // The clearances, from the positions of the search as it found
        // them (the pairs' measures skip none until the next detect stage
        // sets the allowance).
        if let Some(margin) = margin {
            let thickness = self.settings.thickness;
            let reach = thickness + margin;
            for p in &mut pairs.point_triangle {
                p.clearance = p.clearance_at(&at, thickness, reach);
            }
            for p in &mut pairs.point_segment {
                p.clearance = p.clearance_at(&at, thickness, reach);
            }
            for p in &mut pairs.edge_edge {
                p.clearance = beyond(p.distance_at(&at), thickness);
            }
            for p in &mut pairs.point_point {
                let gap = at[p.first as usize] - at[p.second as usize];
                p.clearance = beyond(gap.length(), thickness);
            }
            pairs.bucket(margin / CLEARANCE_BUCKETS as Real, &mut Spare::default());
        }
        self.pairs = pairs;
        match margin {
            Some(margin) => self.scratch.searched(bodies, &at, margin, &self.settings),
            None => self.scratch = Scratch::default(),
        }
        Ok(())
    }
}

fn bad(name: &str, index: usize, value: Real) -> StateError {
    StateError::BadValue {
        name: name.to_string(),
        index,
        value,
    }
}
