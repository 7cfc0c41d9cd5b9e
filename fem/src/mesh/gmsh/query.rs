//! Queries on a read mesh (groups by name and dimension, element areas, pressure weights, outer
//! nodes, the bulk elements of each edge) and the bookkeeping shared by the reader and the split.

use super::{EdgeMap, Face, MeshError, PhysicalGroup, UnstructuredMesh, key, signed_area};
use nalgebra::{Vector2, Vector3};
use std::collections::{BTreeSet, HashMap};

impl UnstructuredMesh {
    /// Scales every node position by `factor` (the length of one unit of the file's
    /// coordinates [m], e.g. 1e-3 for a mesh drawn in millimetres), so that the mesh is in metres.
    /// Orientation, shapes and groups are unchanged: every check of the reader is relative to the
    /// mesh's own size.
    pub fn scale(&mut self, factor: f64) {
        for p in &mut self.positions {
            *p *= factor;
        }
    }

    /// The named physical group.
    pub fn group(&self, name: &str) -> Result<&PhysicalGroup, MeshError> {
        self.groups.get(name).ok_or_else(|| MeshError::MissingGroup {
            group: name.to_string(),
            available: self.groups.keys().cloned().collect::<Vec<_>>().join(", "),
        })
    }

    /// The named physical group, which must have dimension `dim`; `expected` says so in the
    /// error (e.g. "an interface is a physical curve (dimension 1)").
    pub fn group_of_dim(
        &self,
        name: &str,
        dim: usize,
        expected: &'static str,
    ) -> Result<&PhysicalGroup, MeshError> {
        let g = self.group(name)?;
        if g.dim != dim {
            return Err(MeshError::WrongDimension {
                group: name.to_string(),
                dim: g.dim,
                expected,
            });
        }
        Ok(g)
    }

    /// Area of bulk element `e` [m²], positive for a counter-clockwise element.
    pub fn area(&self, e: usize) -> f64 {
        signed_area(&self.elements[e].nodes, &self.positions)
    }

    /// The nodes of the physical curve `name` and, per node, the vector w_a = −∫ N_a n ds [m] over
    /// its line elements (n the outward unit normal, N_a the node's linear shape function along the
    /// line): a pressure p [Pa] pushing on the curve, t = −p n, gives the consistent nodal forces
    /// f_a = p w_a [N/m]. Each line must be on the outer boundary (one bulk element beside it),
    /// which fixes its outward side whatever the line's direction.
    pub fn pressure_weights(&self, name: &str) -> Result<(Vec<usize>, Vec<Vector2<f64>>), MeshError> {
        self.per_outer_line(name, Vector2::zeros(), |face| {
            // the element runs counter-clockwise, so its edge p → q has the body on its left and
            // the outward normal times the length is (d_y, −d_x)
            let el = &self.elements[face.element].nodes;
            let (p, q) = (el[face.local_edge], el[(face.local_edge + 1) % el.len()]);
            let d = self.positions[q] - self.positions[p];
            -0.5 * Vector2::new(d.y, -d.x)
        })
    }

    /// The nodes of the physical curve `name` and, per node, the lumped dashpot of a viscous
    /// (Lysmer–Kuhlemeyer) absorbing boundary, Σ ½ L [ρc_s I + (ρc_d − ρc_s) n nᵀ] over its line
    /// elements, as the symmetric (xx, xy, yy) [N·s/m²]: ρc_d on the normal and ρc_s on the
    /// tangential velocity, of the material of the bulk element beside each line.
    /// `impedance(e)` gives (ρc_d, ρc_s) [kg/(m²·s)] of bulk element e. Each line must be on the
    /// outer boundary, as for [`Self::pressure_weights`].
    pub fn dashpot_weights(
        &self,
        name: &str,
        impedance: &dyn Fn(usize) -> (f64, f64),
    ) -> Result<(Vec<usize>, Vec<[f64; 3]>), MeshError> {
        let (nodes, w) = self.per_outer_line(name, Vector3::zeros(), |face| {
            let el = &self.elements[face.element].nodes;
            let (p, q) = (el[face.local_edge], el[(face.local_edge + 1) % el.len()]);
            let d = self.positions[q] - self.positions[p];
            let length = d.norm();
            let n = Vector2::new(d.y, -d.x) / length;
            let (zd, zs) = impedance(face.element);
            0.5 * length
                * Vector3::new(
                    zs + (zd - zs) * n.x * n.x,
                    (zd - zs) * n.x * n.y,
                    zs + (zd - zs) * n.y * n.y,
                )
        })?;
        Ok((nodes, w.into_iter().map(|c| [c.x, c.y, c.z]).collect()))
    }

    /// The nodes of the physical curve `name` and, per node, the sum over its line elements of
    /// `of_line(face)` at both ends of each line, `face` the bulk element beside the line; each
    /// line must be on the outer boundary (one bulk element beside it).
    fn per_outer_line<T: std::ops::AddAssign + Copy>(
        &self,
        name: &str,
        zero: T,
        of_line: impl Fn(&Face) -> T,
    ) -> Result<(Vec<usize>, Vec<T>), MeshError> {
        let g = self.group_of_dim(name, 1, "a boundary part is a physical curve (dimension 1)")?;
        let edges = self.edge_map();
        let mut w = vec![zero; g.nodes.len()];
        for &l in &g.elements {
            let [a, b] = self.lines[l].nodes;
            let faces = edges.get(&key(a, b)).map_or(&[][..], |f| f.as_slice());
            let [face] = faces else {
                return Err(MeshError::NotOuter {
                    group: name.to_string(),
                    line: self.lines[l].tag,
                    elements: faces.len(),
                });
            };
            g.add_to_ends([a, b], of_line(face), &mut w);
        }
        Ok((g.nodes.clone(), w))
    }

    /// Bulk elements on each edge: key (smaller node, larger node) → (element, local edge).
    pub(super) fn edge_map(&self) -> EdgeMap {
        let mut map: HashMap<(usize, usize), Vec<Face>> = HashMap::new();
        for (e, el) in self.elements.iter().enumerate() {
            let n = el.nodes.len();
            for k in 0..n {
                let (a, b) = (el.nodes[k], el.nodes[(k + 1) % n]);
                map.entry(key(a, b)).or_default().push(Face {
                    element: e,
                    local_edge: k,
                });
            }
        }
        map
    }

    /// Recomputes the node lists of the dim-1 and dim-2 groups from their elements.
    pub(super) fn refresh_group_nodes(&mut self) {
        for g in self.groups.values_mut() {
            let nodes: BTreeSet<usize> = match g.dim {
                2 => g
                    .elements
                    .iter()
                    .flat_map(|&e| self.elements[e].nodes.iter().copied())
                    .collect(),
                1 => g.elements.iter().flat_map(|&l| self.lines[l].nodes).collect(),
                _ => continue,
            };
            g.nodes = nodes.into_iter().collect();
        }
    }

    /// Per node: it lies on the outer boundary (an edge with one element only).
    pub fn outer_nodes(&self) -> Vec<bool> {
        let mut outer = vec![false; self.positions.len()];
        for ((a, b), faces) in self.edge_map() {
            if faces.len() == 1 {
                outer[a] = true;
                outer[b] = true;
            }
        }
        outer
    }
}

/// For each of `n` bulk elements, the first of `surfaces` (element lists, in order) that holds it,
/// `None` for an element in none. Every later surface that holds an element must `agree(first,
/// later)` (surface positions), else Err((element, first, later)).
pub(crate) fn first_surface<'a>(
    n: usize,
    surfaces: impl IntoIterator<Item = &'a [usize]>,
    agree: impl Fn(usize, usize) -> bool,
) -> Result<Vec<Option<usize>>, (usize, usize, usize)> {
    let mut first: Vec<Option<usize>> = vec![None; n];
    for (s, elements) in surfaces.into_iter().enumerate() {
        for &e in elements {
            match first[e] {
                Some(f) if !agree(f, s) => return Err((e, f, s)),
                Some(_) => {}
                None => first[e] = Some(s),
            }
        }
    }
    Ok(first)
}
