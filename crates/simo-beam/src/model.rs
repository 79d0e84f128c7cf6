//! The assembled beam: supports, loads, inertia, and the [`hht::Model`] implementation.

use crate::element::Strains;
use crate::element_block::{cross, dot, rows, BlockForces, BlockStrains, ElementTable};
use crate::error::{not_negative, BeamError};
use crate::mesh::Mesh;
use crate::rotation::skew;
use faer::{Col, ColMut, ColRef};
use hht::{NewtonWeights, Triplets};
use nalgebra::{Matrix3, UnitQuaternion, Vector3};

/// How a node is held. A beam scene's `[[support]]` (and an impact scene's
/// `[[structure.support]]`) names it `kind = "clamped" | "pinned"`; an impact scene's `[beam]`
/// names a pair of them for its two ends (`support = "clamped-free"`, ...).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(
    feature = "scene",
    derive(serde::Serialize, serde::Deserialize, schemars::JsonSchema),
    serde(rename_all = "kebab-case")
)]
pub enum Support {
    /// No constraint (not a support a scene names: a node without one is free).
    #[cfg_attr(feature = "scene", serde(skip))]
    Free,
    /// Position fixed, rotation free.
    Pinned,
    /// Position and the twist about the beam's axis (the node frame's E1) fixed, bending
    /// rotations free: a fork, a simply supported end that holds the section upright (in the
    /// plane, a pin).
    Forked,
    /// Position and rotation fixed.
    Clamped,
}

/// Numbers the free unknowns of nodes held by `supports`, each with N unknowns of which the
/// first `translations` are its position (what a pin holds): the equation number of every
/// node's unknowns (`None` where held) and how many there are. The 3D beam (6 unknowns, 3
/// translations) and the planar one (3, 2) share it.
pub(crate) fn number_unknowns<const N: usize>(
    supports: &[Support],
    translations: usize,
) -> (Vec<[Option<usize>; N]>, usize) {
    let mut n = 0;
    let dofs = supports
        .iter()
        .map(|support| {
            std::array::from_fn(|k| {
                let held = match support {
                    Support::Free => false,
                    Support::Pinned => k < translations,
                    // The twist, the first rotation, where there is one (6 unknowns a node).
                    Support::Forked => k < translations || (N == 6 && k == translations),
                    Support::Clamped => true,
                };
                (!held).then(|| {
                    n += 1;
                    n - 1
                })
            })
        })
        .collect();
    (dofs, n)
}

/// Time variation of a load: the factor multiplying its vectors.
#[derive(Debug, Clone, PartialEq)]
pub enum Profile {
    /// Factor 1 at all times.
    Constant,
    /// Piecewise linear through (time (s), factor) points sorted by time; constant beyond the
    /// ends: before the first point's time the first factor holds (a table starting at
    /// (0.5, 1.0) applies the whole load from t = 0; start it with (0.0, 0.0) for a load that
    /// ramps up from nothing), after the last point's time the last factor.
    Table(Vec<(f64, f64)>),
}

impl Profile {
    /// The factor at time `t` (s).
    pub fn factor(&self, t: f64) -> f64 {
        match self {
            Profile::Constant => 1.0,
            Profile::Table(points) => {
                let (Some(first), Some(last)) = (points.first(), points.last()) else {
                    return 0.0;
                };
                if t <= first.0 {
                    return first.1;
                }
                if t >= last.0 {
                    return last.1;
                }
                for w in points.windows(2) {
                    let ((t0, f0), (t1, f1)) = (w[0], w[1]);
                    if t <= t1 {
                        return if t1 > t0 { f0 + (f1 - f0) * (t - t0) / (t1 - t0) } else { f1 };
                    }
                }
                last.1
            }
        }
    }
}

/// A point load at a node.
#[derive(Debug, Clone, PartialEq)]
pub struct Load {
    /// Node index.
    pub node: usize,
    /// Force (N): spatial if dead, in the node's section frame if follower.
    pub force: Vector3<f64>,
    /// Moment (N m): spatial if dead, in the node's section frame if follower.
    pub moment: Vector3<f64>,
    /// Follower loads turn with the node's section.
    pub follower: bool,
    /// Time variation (dynamics); statics scales by the load factor instead.
    pub profile: Profile,
}

/// Configuration: node positions (m) and section rotations.
#[derive(Debug, Clone, PartialEq)]
pub struct BeamState {
    /// Node positions (m).
    pub positions: Vec<Vector3<f64>>,
    /// Node rotations (map section axes to space).
    pub rotations: Vec<UnitQuaternion<f64>>,
}

/// A meshed beam with supports and loads; implements [`hht::Model`] with six unknowns per free
/// node (displacement increment, then material rotation increment `Lambda <- Lambda exp(th^)`);
/// velocities are spatial for positions and material (body) angular velocities for rotations.
#[derive(Debug, Clone)]
pub struct BeamModel {
    mesh: Mesh,
    /// The elements' constants as arrays, for the internal force's block loop.
    table: ElementTable,
    /// Each node's first unknown where its six are free and in a row.
    rows: Vec<Option<usize>>,
    /// The runs of nodes with their six unknowns in a row, node after node
    /// ([`node_runs`]).
    node_runs: Vec<(usize, usize, usize)>,
    dofs: Vec<[Option<usize>; 6]>,
    ndof: usize,
    loads: Vec<Load>,
    /// Lumped rotational inertia of each node in its material frame (kg m^2).
    node_inertia: Vec<Matrix3<f64>>,
    /// The inertial force's terms sorted for its loop (remade whenever the unknowns or the
    /// inertias change).
    inertia_plan: InertiaPlan,
    /// Multiplies every load in [`hht::Model::net_force`] (statics sets it; 1 in dynamics).
    load_factor: f64,
    /// False in statics: loads are then scaled by the load factor only, not by their profile.
    time_dependent: bool,
    /// Largest section stiffness term, max(EA, GA, GJ/l0, EI/l0) (N): the size of the terms
    /// that cancel in the internal force, hence its round-off floor.
    force_scale: f64,
    /// Point masses (node, kg) on the translations.
    point_masses: Vec<(usize, f64)>,
    /// Translational springs (node, stiffness along x, y, z (N/m)) against the displacement
    /// from the reference position.
    springs: Vec<(usize, Vector3<f64>)>,
    /// Rotational springs (node, stiffness about the section's E1, E2, E3 (N m/rad)) against
    /// the rotation from the reference frame, psi = log(Lambda_0^T Lambda) (material).
    rotational_springs: Vec<(usize, Vector3<f64>)>,
}

impl BeamModel {
    /// A beam on `mesh`, free everywhere and unloaded.
    ///
    /// # Errors
    /// [`BeamError::Mesh`] for a mesh without elements.
    pub fn new(mesh: Mesh) -> Result<Self, BeamError> {
        if mesh.elements.is_empty() {
            return Err(BeamError::Mesh("a beam needs at least one element".into()));
        }
        let nodes = mesh.positions.len();
        let mut node_inertia = vec![Matrix3::zeros(); nodes];
        for e in &mesh.elements {
            let j = Matrix3::from_diagonal(&Vector3::from(e.section.rho_i)) * (0.5 * e.length);
            for end in 0..2 {
                let o = e.offsets[end].to_rotation_matrix().into_inner();
                node_inertia[e.nodes[end]] += o * j * o.transpose();
            }
        }
        let force_scale = mesh
            .elements
            .iter()
            .map(|e| {
                let s = &e.section;
                s.ea.max(s.ga2).max(s.ga3).max(s.gj.max(s.ei2).max(s.ei3) / e.length)
            })
            .fold(0.0, f64::max);
        let mut model = Self {
            table: ElementTable::new(&mesh.elements),
            rows: Vec::new(),
            node_runs: Vec::new(),
            mesh,
            dofs: vec![[None; 6]; nodes],
            ndof: 0,
            loads: Vec::new(),
            node_inertia,
            inertia_plan: InertiaPlan::default(),
            load_factor: 1.0,
            time_dependent: true,
            force_scale,
            point_masses: Vec::new(),
            springs: Vec::new(),
            rotational_springs: Vec::new(),
        };
        model.number(&vec![Support::Free; nodes]);
        Ok(model)
    }

    fn number(&mut self, supports: &[Support]) {
        (self.dofs, self.ndof) = number_unknowns(supports, 3);
        self.rows = rows(&self.dofs);
        self.node_runs = node_runs(&self.rows);
        self.inertia_plan = InertiaPlan::new(self);
    }

    /// Sets the support of `node`.
    ///
    /// # Errors
    /// [`BeamError::Mesh`] for a node index out of range.
    pub fn support(mut self, node: usize, support: Support) -> Result<Self, BeamError> {
        self.check_node(node)?;
        let mut held = self.held();
        let was = held[node];
        // A pin adds to the node's own holds (from `hold`); free releases them all.
        held[node] = std::array::from_fn(|k| match support {
            Support::Free => false,
            Support::Pinned => k < 3 || was[k],
            Support::Forked => k < 4 || was[k],
            Support::Clamped => true,
        });
        self.renumber(&held);
        Ok(self)
    }

    /// Holds the unknowns `holds` (node, k; k 0-2 the displacement along x, y, z, 3-5 the
    /// rotation about the node's material axes E1, E2, E3) at their reference values, as a
    /// support would: for a model reduced to the motions a load can excite (a planar structure
    /// loaded normal to its plane moves only out of it, when linearised at rest).
    ///
    /// # Errors
    /// [`BeamError::Mesh`] for a node or a component out of range.
    pub fn hold(mut self, holds: &[(usize, usize)]) -> Result<Self, BeamError> {
        let mut held = self.held();
        for &(node, k) in holds {
            self.check_node(node)?;
            if k >= 6 {
                return Err(BeamError::Mesh(format!(
                    "unknown {k} of node {node} does not exist (0-2 displacement, 3-5 rotation)"
                )));
            }
            held[node][k] = true;
        }
        self.renumber(&held);
        Ok(self)
    }

    /// Which unknowns of each node are held.
    fn held(&self) -> Vec<[bool; 6]> {
        self.dofs.iter().map(|d| d.map(|x| x.is_none())).collect()
    }

    /// Numbers the unknowns that `held` leaves free, node by node (the band stays as narrow).
    fn renumber(&mut self, held: &[[bool; 6]]) {
        let mut n = 0;
        self.dofs = held
            .iter()
            .map(|h| {
                std::array::from_fn(|k| {
                    (!h[k]).then(|| {
                        n += 1;
                        n - 1
                    })
                })
            })
            .collect();
        self.ndof = n;
        self.rows = rows(&self.dofs);
        self.node_runs = node_runs(&self.rows);
        self.inertia_plan = InertiaPlan::new(self);
    }

    /// Adds a point mass of `mass` (kg) at `node`, with `rotary_inertia` (kg m^2) about the
    /// node's section axes E1 (the member's axis: a sensor's, a tip mass's resistance to
    /// twist), E2 and E3 (to the bending rotations). At a corner the node's section is the
    /// member's that reaches it.
    ///
    /// # Errors
    /// [`BeamError::Mesh`] for a node out of range; [`BeamError::InvalidParameter`] for a
    /// value that is negative or not finite.
    pub fn attach_mass(
        mut self,
        node: usize,
        mass: f64,
        rotary_inertia: [f64; 3],
    ) -> Result<Self, BeamError> {
        self.check_node(node)?;
        not_negative("mass", mass, "a finite number >= 0 (kg)")?;
        for value in rotary_inertia {
            not_negative("rotary_inertia", value, "finite components >= 0 (kg m^2)")?;
        }
        self.point_masses.push((node, mass));
        for (axis, value) in rotary_inertia.into_iter().enumerate() {
            self.node_inertia[node][(axis, axis)] += value;
        }
        self.inertia_plan = InertiaPlan::new(&self);
        Ok(self)
    }

    /// Adds a translational spring at `node`: `stiffness` (N/m) along x, y and z against the
    /// node's displacement from its reference position.
    ///
    /// # Errors
    /// As [`BeamModel::attach_mass`].
    pub fn attach_spring(
        mut self,
        node: usize,
        stiffness: Vector3<f64>,
    ) -> Result<Self, BeamError> {
        self.check_node(node)?;
        for value in stiffness.iter() {
            not_negative("stiffness", *value, "finite components >= 0 (N/m)")?;
        }
        self.springs.push((node, stiffness));
        Ok(self)
    }

    /// Adds a rotational spring at `node`: `stiffness` (N m/rad) about the section's axes E1,
    /// E2, E3 against its rotation from the reference frame, the energy
    /// `psi . K psi / 2` with `psi = log(Lambda_0^T Lambda)`. Its moment on the material
    /// increment is `J_r^-T(psi) K psi` (exact); its tangent the leading `J_r^-T K J_r^-1` (the
    /// term of the Jacobian's own rate, of order |psi| |K psi|, is left to Newton).
    ///
    /// # Errors
    /// As [`BeamModel::attach_mass`].
    pub fn attach_rotational_spring(
        mut self,
        node: usize,
        stiffness: Vector3<f64>,
    ) -> Result<Self, BeamError> {
        self.check_node(node)?;
        for value in stiffness.iter() {
            not_negative("rotational_stiffness", *value, "finite components >= 0 (N m/rad)")?;
        }
        self.rotational_springs.push((node, stiffness));
        Ok(self)
    }

    /// The nodes that carry a point mass or a spring of either kind (each once, ascending):
    /// where a bending moment may kink or jump (a mass's inertia, a spring's force or moment).
    pub fn attachment_nodes(&self) -> Vec<usize> {
        let mut nodes: Vec<usize> = self
            .point_masses
            .iter()
            .map(|(node, _)| *node)
            .chain(self.springs.iter().map(|(node, _)| *node))
            .chain(self.rotational_spring_nodes())
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes
    }

    /// The nodes that carry a rotational spring ([`BeamModel::attach_rotational_spring`]).
    pub fn rotational_spring_nodes(&self) -> impl Iterator<Item = usize> + '_ {
        self.rotational_springs.iter().map(|(node, _)| *node)
    }

    /// A node's rotation from its reference frame, psi = log(Lambda_0^T Lambda) (rad, material).
    fn turned(&self, q: &BeamState, node: usize) -> Vector3<f64> {
        (self.mesh.frames[node].inverse() * q.rotations[node]).scaled_axis()
    }

    /// The springs' stored energy (J).
    pub fn spring_energy(&self, q: &BeamState) -> f64 {
        let translational: f64 = self
            .springs
            .iter()
            .map(|(node, k)| {
                let u = q.positions[*node] - self.mesh.positions[*node];
                0.5 * k.component_mul(&u).dot(&u)
            })
            .sum();
        let rotational: f64 = self
            .rotational_springs
            .iter()
            .map(|(node, k)| {
                let psi = self.turned(q, *node);
                0.5 * k.component_mul(&psi).dot(&psi)
            })
            .sum();
        translational + rotational
    }

    fn check_node(&self, node: usize) -> Result<(), BeamError> {
        if node >= self.mesh.positions.len() {
            return Err(BeamError::Mesh(format!(
                "node {node} does not exist (the mesh has {} nodes)",
                self.mesh.positions.len()
            )));
        }
        Ok(())
    }

    /// Adds a load at a node.
    ///
    /// # Errors
    /// [`BeamError::Mesh`] for a node out of range, [`BeamError::InvalidParameter`] for a
    /// non-finite vector.
    pub fn load(mut self, load: Load) -> Result<Self, BeamError> {
        self.check_node(load.node)?;
        for v in load.force.iter().chain(load.moment.iter()) {
            if !v.is_finite() {
                return Err(BeamError::InvalidParameter {
                    name: "load",
                    value: *v,
                    allowed: "finite force (N) and moment (N m) components",
                });
            }
        }
        self.loads.push(load);
        Ok(self)
    }

    /// Adds a load at arc length `s` (m) from the first node, shared between the two nodes of
    /// the element that holds it in proportion to the linear shape functions.
    ///
    /// # Errors
    /// As [`BeamModel::load`]; [`BeamError::InvalidParameter`] for `s` outside the beam.
    pub fn load_at(self, s: f64, load: Load) -> Result<Self, BeamError> {
        let total = self.mesh.arc_length.last().copied().unwrap_or(0.0);
        if !(s.is_finite() && (0.0..=total).contains(&s)) {
            return Err(BeamError::InvalidParameter {
                name: "load arc length",
                value: s,
                allowed: "a position along the beam, from 0 to its length (m)",
            });
        }
        let i = self.mesh.arc_length.windows(2).position(|w| s <= w[1]).unwrap_or(0);
        let (s0, s1) = (self.mesh.arc_length[i], self.mesh.arc_length[i + 1]);
        let xi = (s - s0) / (s1 - s0);
        let a = Load {
            node: i,
            force: load.force * (1.0 - xi),
            moment: load.moment * (1.0 - xi),
            ..load.clone()
        };
        let b = Load { node: i + 1, force: load.force * xi, moment: load.moment * xi, ..load };
        self.load(a)?.load(b)
    }

    /// The mesh.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// Removes every load.
    pub fn clear_loads(&mut self) {
        self.loads.clear();
    }

    /// Sets the factor that multiplies every load (statics uses it as the load parameter).
    pub fn set_load_factor(&mut self, factor: f64) {
        self.load_factor = factor;
    }

    /// Equation number of `node`'s unknown `k` (0-2 displacement, 3-5 rotation), if free.
    pub fn dof(&self, node: usize, k: usize) -> Option<usize> {
        self.dofs.get(node).and_then(|d| d.get(k).copied().flatten())
    }

    /// The undeformed configuration.
    pub fn reference_state(&self) -> BeamState {
        BeamState { positions: self.mesh.positions.clone(), rotations: self.mesh.frames.clone() }
    }

    /// The node's three unknowns from `offset` (0 the displacement, 3 the rotation) in `x`,
    /// zero where held.
    #[inline(always)]
    fn node_vector(&self, x: &[f64], node: usize, offset: usize) -> Vector3<f64> {
        if let Some(i) = self.rows[node] {
            let x = &x[i + offset..i + offset + 3];
            return Vector3::new(x[0], x[1], x[2]);
        }
        Vector3::from_fn(|k, _| self.dofs[node][offset + k].map_or(0.0, |i| x[i]))
    }

    /// Adds `f` to the node's three unknowns from `offset` in `out` (none where held).
    #[inline(always)]
    fn add_node_vector(&self, out: &mut [f64], node: usize, offset: usize, f: &Vector3<f64>) {
        if let Some(i) = self.rows[node] {
            for (o, f) in out[i + offset..i + offset + 3].iter_mut().zip(f.iter()) {
                *o += f;
            }
            return;
        }
        for k in 0..3 {
            if let Some(i) = self.dofs[node][offset + k] {
                out[i] += f[k];
            }
        }
    }

    fn factor(&self, t: f64, load: &Load) -> f64 {
        let profile = if self.time_dependent { load.profile.factor(t) } else { 1.0 };
        profile * self.load_factor
    }

    /// Switches loads between static use (load factor only) and dynamic use (profile times
    /// load factor).
    pub(crate) fn set_time_dependent(&mut self, on: bool) {
        self.time_dependent = on;
    }

    fn external(&self, t: f64, q: &BeamState, load: &Load) -> (Vector3<f64>, Vector3<f64>) {
        let p = self.factor(t, load);
        let r = q.rotations[load.node];
        if load.follower {
            (r * load.force * p, load.moment * p)
        } else {
            (load.force * p, r.inverse() * load.moment * p)
        }
    }

    /// The largest section strains of `q` over the elements: the axial strain's magnitude and
    /// the shear strain's (the two transverse components' norm), both dimensionless. The
    /// section law is linear elastic: a small-strain law, meant for strains up to a few per
    /// cent at most.
    pub fn largest_strains(&self, q: &BeamState) -> (f64, f64) {
        self.mesh.elements.iter().fold((0.0, 0.0), |(axial, shear), e| {
            let [a, b] = e.nodes;
            let g = e
                .strains([&q.positions[a], &q.positions[b]], [&q.rotations[a], &q.rotations[b]])
                .gamma;
            (axial.max(g[0].abs()), shear.max(g[1].hypot(g[2])))
        })
    }

    /// Hands every element's strains at `q` to `each` (the element's index and its strains,
    /// in the mesh's order): no buffer, for a loop that reads them at every step.
    pub fn each_strain(&self, q: &BeamState, each: impl FnMut(usize, Strains<f64>)) {
        crate::element_block::with_scratch(|scratch| {
            hht::fast::run(BlockStrains {
                elements: &self.mesh.elements,
                table: &self.table,
                positions: &q.positions,
                rotations: &q.rotations,
                each,
                scratch,
            })
        });
    }

    /// [`hht::Model::net_force`] that also writes every element's strains at `q` into
    /// `strains` (Gamma1, Gamma2, Gamma3, K1, K2, K3: an array each, an entry an element,
    /// resized to the elements padded to whole blocks of the element pass: the entries past
    /// the last element are not strains), from the same pass: a step's last force evaluation then
    /// gives its state's strains without a second pass over the elements' rotations.
    pub fn net_force_and_strains(
        &self,
        t: f64,
        q: &BeamState,
        out: ColMut<'_, f64>,
        strains: &mut [Vec<f64>; 6],
    ) {
        // (Padded past the last element to whole blocks: the element pass writes a block's
        // strains where it computes them.)
        for s in strains.iter_mut() {
            s.resize(self.table.padded(), 0.0);
        }
        write_to(out, |out| self.net_force_into(t, q, out, Some(strains)));
    }

    /// Strain energy (J).
    pub fn strain_energy(&self, q: &BeamState) -> f64 {
        self.mesh
            .elements
            .iter()
            .map(|e| {
                let [a, b] = e.nodes;
                e.energy([&q.positions[a], &q.positions[b]], [&q.rotations[a], &q.rotations[b]])
            })
            .sum::<f64>()
            + self.spring_energy(q)
    }

    /// Kinetic energy (J) for velocity `v` (consistent translational mass, lumped rotary).
    pub fn kinetic_energy(&self, v: ColRef<'_, f64>) -> f64 {
        let v = &*values(v);
        // The inertial force's plan (`InertiaPlan`): the usual elements and nodes read as
        // arrays, the rest by index (through the elements themselves and nalgebra a node, the
        // accepted rows' energy took 1.9 % of the paper's tip in 3D).
        let plan = &self.inertia_plan;
        let translation = |va: &[f64; 3], vb: &[f64; 3]| {
            (0..3).map(|c| va[c] * va[c] + va[c] * vb[c] + vb[c] * vb[c]).sum::<f64>()
        };
        let spinning = |(w, d): (&[f64; 3], &[f64; 3])| {
            0.5 * (d[0] * w[0] * w[0] + d[1] * w[1] * w[1] + d[2] * w[2] * w[2])
        };
        // A run's elements and nodes in four partial sums, element or node k into sum k mod 4
        // (one chain of additions, its latency set the time: 1.2 % of the paper's tip in 3D,
        // which asks at every recorded instant), then the rest in the order of their lists.
        let mut parts = [0.0; 4];
        for run in &plan.runs {
            let span = &v[run.first..run.first + 6 * run.spin.len()];
            let pairs = span.windows(9).step_by(6).zip(&run.masses);
            for (k, (pair, m)) in pairs.enumerate() {
                parts[k % 4] += m * translation(three(pair, 0), three(pair, 6));
            }
            for (k, (node, d)) in span.chunks_exact(6).zip(&run.spin).enumerate() {
                parts[k % 4] += spinning((three(node, 3), d));
            }
        }
        let mut energy = (parts[0] + parts[1]) + (parts[2] + parts[3]);
        for &(ia, ib, m) in &plan.chain {
            energy += m * translation(three(v, ia), three(v, ib));
        }
        let masses = self.table.translational_masses();
        for &e in &plan.other_elements {
            let ([a, b], m) = (self.table.nodes()[e], masses[e]);
            let (va, vb) = (self.node_vector(v, a, 0), self.node_vector(v, b, 0));
            energy += m * translation(&va.into(), &vb.into());
        }
        for (i, d) in &plan.spinning {
            energy += spinning((three(v, i + 3), d));
        }
        for &node in &plan.other_nodes {
            let w = self.node_vector(v, node, 3);
            energy += 0.5 * w.dot(&(self.node_inertia[node] * w));
        }
        for (node, m) in &self.point_masses {
            energy += 0.5 * m * self.node_vector(v, *node, 0).norm_squared();
        }
        energy
    }

    /// Internal forces at `q` as a full vector over free unknowns (N, N m).
    pub fn internal_force(&self, q: &BeamState) -> Col<f64> {
        let mut out = Col::zeros(self.ndof);
        write_to(out.as_mut(), |out| self.add_internal(q, (out, false), None));
        out
    }

    /// Adds (or with `write`, writes: [`BlockForces::write`]) the internal forces into `out`.
    fn add_internal(
        &self,
        q: &BeamState,
        out: (&mut [f64], bool),
        strains: Option<&mut [Vec<f64>; 6]>,
    ) {
        self.add_internal_on(q, out, strains, true);
    }

    /// [`BeamModel::add_internal`] in `hht::fast::run_wide`'s copy with `wide` (what the
    /// model runs), else in `hht::fast::run`'s (the tests hold the two to the same bits).
    pub(crate) fn add_internal_on(
        &self,
        q: &BeamState,
        (out, write): (&mut [f64], bool),
        strains: Option<&mut [Vec<f64>; 6]>,
        wide: bool,
    ) {
        crate::element_block::with_scratch(|scratch| {
            let kernel = BlockForces {
                write,
                elements: &self.mesh.elements,
                table: &self.table,
                positions: &q.positions,
                rotations: &q.rotations,
                dofs: &self.dofs,
                rows: &self.rows,
                out,
                strains,
                scratch,
            };
            if wide {
                hht::fast::run_wide(kernel)
            } else {
                hht::fast::run(kernel)
            }
        });
    }

    /// Pushes a 3x3 block for (node_a, offset_a) x (node_b, offset_b), always the same entries.
    #[allow(clippy::too_many_arguments)]
    fn push_block(
        &self,
        out: &mut Triplets,
        a: usize,
        oa: usize,
        b: usize,
        ob: usize,
        block: &Matrix3<f64>,
    ) {
        for i in 0..3 {
            let Some(row) = self.dofs[a][oa + i] else { continue };
            for j in 0..3 {
                if let Some(col) = self.dofs[b][ob + j] {
                    out.push(row, col, block[(i, j)]);
                }
            }
        }
    }

    /// A node's position and rotation moved by its unknowns in `dq`: `x + u`, `r exp(th^)`.
    #[inline(always)]
    fn displaced_node(
        &self,
        (x, r): (&Vector3<f64>, &UnitQuaternion<f64>),
        dq: &[f64],
        node: usize,
    ) -> (Vector3<f64>, UnitQuaternion<f64>) {
        let th = self.node_vector(dq, node, 3);
        let r = if th.norm_squared() > 0.0 { r * crate::rotation::exp(&th) } else { *r };
        (x + self.node_vector(dq, node, 0), r)
    }

    fn inertial_force_into(&self, v: &[f64], a: &[f64], out: &mut [f64]) {
        hht::fast::run(Inertia { model: self, v, a, out });
    }

    #[inline(always)]
    fn inertial_force_inline(&self, v: &[f64], a: &[f64], out: &mut [f64]) {
        let plan = &self.inertia_plan;
        for unwritten in &plan.unwritten {
            out[unwritten.clone()].fill(0.0);
        }
        for run in &plan.runs {
            run.write(v, a, out);
        }
        // Both nodes' three translations in a row (the usual case): read and written as
        // arrays, not looked up an unknown at a time. The first nodes' terms, then the second
        // nodes': within a pass no element writes what the one before wrote, so the loop does
        // not wait on its own stores (neighbours share a node).
        for &(ia, ib, m) in &plan.chain {
            let (x, y) = (three(a, ia), three(a, ib));
            let f: [f64; 3] = std::array::from_fn(|c| m * (2.0 * x[c] + y[c]));
            three_mut(out, ia).iter_mut().zip(f).for_each(|(o, f)| *o += f);
        }
        for &(ia, ib, m) in &plan.chain {
            let (x, y) = (three(a, ia), three(a, ib));
            let f: [f64; 3] = std::array::from_fn(|c| m * (x[c] + 2.0 * y[c]));
            three_mut(out, ib).iter_mut().zip(f).for_each(|(o, f)| *o += f);
        }
        let masses = self.table.translational_masses();
        for &e in &plan.other_elements {
            let ([na, nb], m) = (self.table.nodes()[e], masses[e]);
            let (aa, ab) = (self.node_vector(a, na, 0), self.node_vector(a, nb, 0));
            self.add_node_vector(out, na, 0, &((2.0 * aa + ab) * m));
            self.add_node_vector(out, nb, 0, &((aa + 2.0 * ab) * m));
        }
        for (node, m) in &self.point_masses {
            let a = self.node_vector(a, *node, 0);
            self.add_node_vector(out, *node, 0, &(a * *m));
        }
        for &(i, d) in &plan.spinning {
            // Euler's equation with J diagonal (a section's principal axes, the usual case).
            let f = euler(&d, three(v, i + 3), three(a, i + 3));
            three_mut(out, i + 3).iter_mut().zip(f).for_each(|(o, f)| *o += f);
        }
        for &node in &plan.other_nodes {
            let j = &self.node_inertia[node];
            let w = self.node_vector(v, node, 3);
            let dw = self.node_vector(a, node, 3);
            self.add_node_vector(out, node, 3, &(j * dw + w.cross(&(j * w))));
        }
    }

    fn net_force_into(
        &self,
        t: f64,
        q: &BeamState,
        out: &mut [f64],
        strains: Option<&mut [Vec<f64>; 6]>,
    ) {
        // One chain from node 0 writes every unknown: no zeroing first.
        let write = self.table.one_chain(self.mesh.positions.len());
        if !write {
            out.fill(0.0);
        }
        self.add_internal(q, (out, write), strains);
        for (node, k) in &self.springs {
            let u = q.positions[*node] - self.mesh.positions[*node];
            self.add_node_vector(out, *node, 0, &k.component_mul(&u));
        }
        for (node, k) in &self.rotational_springs {
            let psi = self.turned(q, *node);
            let moment =
                crate::rotation::right_jacobian_inverse(&psi).transpose() * k.component_mul(&psi);
            self.add_node_vector(out, *node, 3, &moment);
        }
        for load in &self.loads {
            let (f, m) = self.external(t, q, load);
            self.add_node_vector(out, load.node, 0, &(-f));
            self.add_node_vector(out, load.node, 3, &(-m));
        }
    }
}

/// The runs of nodes whose six unknowns follow each other node after node: (first node, its
/// first unknown, nodes), node `first + k`'s unknowns from `unknown + 6 k`.
fn node_runs(rows: &[Option<usize>]) -> Vec<(usize, usize, usize)> {
    let mut runs: Vec<(usize, usize, usize)> = Vec::new();
    for (node, row) in rows.iter().enumerate() {
        let Some(row) = *row else { continue };
        match runs.last_mut() {
            Some((first, unknown, count))
                if *first + *count == node && *unknown + 6 * *count == row =>
            {
                *count += 1;
            }
            _ => runs.push((node, row, 1)),
        }
    }
    runs
}

/// Whether `j`'s off-diagonal entries are all zero.
fn is_diagonal(j: &Matrix3<f64>) -> bool {
    (0..3).all(|r| (0..3).all(|c| r == c || j[(r, c)] == 0.0))
}

/// The three entries of `x` from `i`.
#[inline(always)]
fn three(x: &[f64], i: usize) -> &[f64; 3] {
    #[allow(clippy::expect_used)] // a slice of three is three long
    x[i..i + 3].try_into().expect("three entries")
}

/// [`three`], to write.
#[inline(always)]
fn three_mut(x: &mut [f64], i: usize) -> &mut [f64; 3] {
    #[allow(clippy::expect_used)] // a slice of three is three long
    (&mut x[i..i + 3]).try_into().expect("three entries")
}

/// [`BeamModel`]'s inertial force terms sorted by the path its loop takes, so that the loop
/// itself neither looks up which unknowns are held nor tests an inertia for its axes: the
/// elements whose two nodes have their six unknowns numbered in a row, and the nodes with
/// theirs in a row and a diagonal rotary inertia (the usual case: every node but a support's),
/// each with what its terms need; the others by index, for the general path. (Looking this
/// up node by node took 2.3 us an inertial force on the paper's strip at 256 elements in 3D.)
#[derive(Debug, Clone, Default)]
struct InertiaPlan {
    /// Runs of nodes written node by node (the usual mesh: all its free nodes in one run).
    runs: Vec<InertiaRun>,
    /// The unknowns no run writes (zeroed first: the terms below add to them).
    unwritten: Vec<std::ops::Range<usize>>,
    /// (first unknown of node a, of node b, `rho A l0 / 6` (kg)), elements in no run.
    chain: Vec<(usize, usize, f64)>,
    /// The elements with a node whose six unknowns are not all free and in a row.
    other_elements: Vec<usize>,
    /// (first unknown of the node, its rotary inertia's diagonal (kg m^2)), nodes in no run.
    spinning: Vec<(usize, [f64; 3])>,
    /// The nodes neither in a run nor in `spinning`.
    other_nodes: Vec<usize>,
    /// Whether every free rotation is a run's (no node of `spinning`, none of `other_nodes`
    /// with a free rotation): the rotations' rows then take no other term.
    rotations_in_runs: bool,
}

/// Nodes whose six unknowns follow each other node after node (node j's from `first + 6 j`),
/// joined in order by elements, each with a diagonal rotary inertia: their inertial force is
/// written node by node, each node's six once, with no zeroing before and no element's terms
/// added to a node the element before wrote (one pass instead of three: 1.35 -> 0.83 us an
/// inertial force on the paper's strip at 256 elements in 3D).
#[derive(Debug, Clone, Default)]
struct InertiaRun {
    first: usize,
    /// Each node's rotary inertia's diagonal (kg m^2).
    spin: Vec<[f64; 3]>,
    /// `rho A l0 / 6` (kg) of the element from node j to node j + 1 (one fewer than nodes).
    masses: Vec<f64>,
}

impl InertiaPlan {
    fn new(model: &BeamModel) -> Self {
        let mut plan = Self::default();
        let (nodes, masses) = (model.table.nodes(), model.table.translational_masses());
        let spin = |node: usize| {
            let j = &model.node_inertia[node];
            is_diagonal(j).then(|| [j[(0, 0)], j[(1, 1)], j[(2, 2)]])
        };
        // The runs, element by element: an element joins the last run where it starts at the
        // run's last node, or starts one; a node is in one run at most.
        let mut in_run = vec![false; model.rows.len()];
        for (e, (&[na, nb], &m)) in nodes.iter().zip(masses).enumerate() {
            let (Some(ia), Some(ib)) = (model.rows[na], model.rows[nb]) else {
                plan.other_elements.push(e);
                continue;
            };
            let joins = ib == ia + 6 && !in_run[nb] && spin(nb).is_some();
            let last = plan.runs.last_mut().filter(|r| r.first + 6 * (r.spin.len() - 1) == ia);
            match (joins, last) {
                (true, Some(run)) if in_run[na] => {
                    run.spin.extend(spin(nb));
                    run.masses.push(m);
                    in_run[nb] = true;
                }
                (true, _) if !in_run[na] && spin(na).is_some() => {
                    let spin = [spin(na), spin(nb)].into_iter().flatten().collect();
                    plan.runs.push(InertiaRun { first: ia, spin, masses: vec![m] });
                    (in_run[na], in_run[nb]) = (true, true);
                }
                _ => plan.chain.push((ia, ib, m)),
            }
        }
        for (node, j) in model.node_inertia.iter().enumerate() {
            match (model.rows[node], is_diagonal(j)) {
                _ if in_run[node] => {}
                (Some(i), true) => plan.spinning.push((i, [j[(0, 0)], j[(1, 1)], j[(2, 2)]])),
                _ => plan.other_nodes.push(node),
            }
        }
        plan.rotations_in_runs = plan.spinning.is_empty()
            && plan
                .other_nodes
                .iter()
                .all(|&node| model.dofs[node][3..].iter().all(Option::is_none));
        let mut written: Vec<_> =
            plan.runs.iter().map(|r| (r.first, r.first + 6 * r.spin.len())).collect();
        written.sort_unstable();
        let mut from = 0;
        for (start, end) in written {
            if start > from {
                plan.unwritten.push(from..start);
            }
            from = end;
        }
        if model.ndof > from {
            plan.unwritten.push(from..model.ndof);
        }
        plan
    }
}

/// `J dW/dt + W x J W`, Euler's equation in the body frame, for a diagonal `J = diag(d)`.
#[inline(always)]
fn euler(d: &[f64; 3], w: &[f64; 3], dw: &[f64; 3]) -> [f64; 3] {
    let jw = [d[0] * w[0], d[1] * w[1], d[2] * w[2]];
    [
        d[0] * dw[0] + (w[1] * jw[2] - w[2] * jw[1]),
        d[1] * dw[1] + (w[2] * jw[0] - w[0] * jw[2]),
        d[2] * dw[2] + (w[0] * jw[1] - w[1] * jw[0]),
    ]
}

/// A run's node's six rows of the inertial force: its translations' `f`, then Euler's equation
/// for its rotary inertia's diagonal `d` at the node's angular velocity and acceleration (rows
/// 3..6 of `v` and `a`).
#[inline(always)]
fn write_node(out: &mut [f64], f: [f64; 3], d: &[f64; 3], (v, a): (&[f64], &[f64])) {
    let r = euler(d, &[v[3], v[4], v[5]], &[a[3], a[4], a[5]]);
    out.copy_from_slice(&[f[0], f[1], f[2], r[0], r[1], r[2]]);
}

impl InertiaRun {
    /// Writes the run's inertial force into `out` for velocity `v` and acceleration `a`. A
    /// node's translation: its element to the next node's term `m (2 a_j + a_(j+1))`, then
    /// the element from the last node's `m (a_(j-1) + 2 a_j)` (the sum in the element loops'
    /// order, where no element outside the run reaches the node).
    #[inline(always)]
    fn write(&self, v: &[f64], a: &[f64], out: &mut [f64]) {
        let n = self.spin.len();
        let span = self.first..self.first + 6 * n;
        let (v, a, out) = (&v[span.clone()], &a[span.clone()], &mut out[span]);
        // Element j from node j to node j + 1 (its two nodes' accelerations `pair`): node j's
        // force is its term ahead plus the last element's term behind (`behind`).
        let mut behind: Option<[f64; 3]> = None;
        let elements = a.windows(12).step_by(6).zip(&self.masses);
        let nodes = out.chunks_exact_mut(6).zip(v.chunks_exact(6)).zip(&self.spin);
        for (((out, v), d), (pair, &m)) in nodes.zip(elements) {
            let ahead: [f64; 3] = std::array::from_fn(|c| m * (2.0 * pair[c] + pair[6 + c]));
            let f = match behind {
                Some(b) => std::array::from_fn(|c| ahead[c] + b[c]),
                None => ahead,
            };
            write_node(out, f, d, (v, pair));
            behind = Some(std::array::from_fn(|c| m * (pair[c] + 2.0 * pair[6 + c])));
        }
        let last = 6 * (n - 1);
        if let (Some(b), Some(d)) = (behind, self.spin.last()) {
            write_node(&mut out[last..], b, d, (&v[last..], &a[last..]));
        }
    }

    /// [`InertiaRun::write`] where `old` holds the inertial force at the same acceleration
    /// `a` and another velocity: the translations' rows are `old`'s (the same arithmetic on
    /// the same `a`: the same bits), the rotations' Euler's equation at `v`, as `write`'s.
    #[inline(always)]
    fn write_spin(&self, v: &[f64], a: &[f64], old: &[f64], out: &mut [f64]) {
        let span = self.first..self.first + 6 * self.spin.len();
        let (v, a) = (&v[span.clone()], &a[span.clone()]);
        let (old, out) = (&old[span.clone()], &mut out[span]);
        let rates = v.chunks_exact(6).zip(a.chunks_exact(6));
        let nodes = out.chunks_exact_mut(6).zip(old.chunks_exact(6)).zip(rates);
        for (((out, old), (v, a)), d) in nodes.zip(&self.spin) {
            write_node(out, [old[0], old[1], old[2]], d, (v, a));
        }
    }
}

/// [`hht::Model::displaced`] of the 3D beam as a [`hht::fast::Kernel`]: `out = q (+) dq`.
struct Displace<'a> {
    model: &'a BeamModel,
    q: &'a BeamState,
    dq: &'a [f64],
    out: &'a mut BeamState,
}

impl hht::fast::Kernel for Displace<'_> {
    type Output = ();

    #[inline(always)]
    fn run<A: hht::fast::MulAdd>(self, m: A) {
        let (model, q, dq) = (self.model, self.q, self.dq);
        let (positions, rotations) = (&mut self.out.positions, &mut self.out.rotations);
        // A node by its exact update (nalgebra's exponential), one at a time.
        let exact =
            |node: usize| model.displaced_node((&q.positions[node], &q.rotations[node]), dq, node);
        // (Only the nodes the state has: the caller's `out` is sized to them.)
        let nodes = q.positions.len().min(model.rows.len());
        let mut done = 0;
        for &(first, unknown, count) in &model.node_runs {
            let end = (first + count).min(nodes);
            // The nodes before this run (none with all six unknowns in a row).
            for node in done..first.min(nodes) {
                (positions[node], rotations[node]) = exact(node);
            }
            done = end.max(first.min(nodes));
            if first >= end {
                break;
            }
            let from = q.positions[first..end].iter().zip(&q.rotations[first..end]);
            let to = positions[first..end].iter_mut().zip(rotations[first..end].iter_mut());
            let rows = dq[unknown..unknown + 6 * (end - first)].chunks_exact(6);
            // Every node by the series of `rotation::exp` and the product `r0 exp(th)` written
            // out with multiply-adds, in one loop without branches (node by node through
            // nalgebra's types a node took 7 ns, the paper's strip in 3D; with a branch a node
            // on the turn's size, 5.3 ns); then the nodes turned past it again exactly.
            let turn2 = |d: &[f64]| m.mul_add(d[3], d[3], m.mul_add(d[4], d[4], d[5] * d[5]));
            let past = |a2: f64| a2 >= crate::rotation::SERIES_BELOW || a2.is_nan();
            let mut beyond = false;
            for ((d, (x0, r0)), (x, r)) in rows.clone().zip(from).zip(to) {
                let th = [d[3], d[4], d[5]];
                let a2 = turn2(d);
                beyond |= past(a2);
                let (w, s) = crate::rotation::exp_series_coefficients(m, a2);
                let v = th.map(|t| t * s);
                let q0 = r0.quaternion();
                let (w0, u) = (q0.w, [q0.i, q0.j, q0.k]);
                let uv = cross(m, u, v);
                let iv: [f64; 3] =
                    std::array::from_fn(|c| m.mul_add(w0, v[c], m.mul_add(w, u[c], uv[c])));
                let turned =
                    nalgebra::Quaternion::new(m.mul_add(w0, w, -dot(m, u, v)), iv[0], iv[1], iv[2]);
                *x = Vector3::new(x0.x + d[0], x0.y + d[1], x0.z + d[2]);
                *r = UnitQuaternion::new_unchecked(turned);
            }
            if beyond {
                for (k, d) in rows.enumerate() {
                    if past(turn2(d)) {
                        (positions[first + k], rotations[first + k]) = exact(first + k);
                    }
                }
            }
        }
        for node in done..nodes {
            (positions[node], rotations[node]) = exact(node);
        }
    }
}

/// [`BeamModel::inertial_force`] as a [`hht::fast::Kernel`].
struct Inertia<'a> {
    model: &'a BeamModel,
    v: &'a [f64],
    a: &'a [f64],
    out: &'a mut [f64],
}

impl hht::fast::Kernel for Inertia<'_> {
    type Output = ();

    #[inline(always)]
    fn run<A: hht::fast::MulAdd>(self, _: A) {
        self.model.inertial_force_inline(self.v, self.a, self.out);
    }
}

/// [`hht::Model::predicted_inertial_force`] of a beam whose free rotations are all in runs:
/// the translations' rows (and the rows no run writes: translations only, as the runs hold
/// every free rotation) copied from `old`, each run's rotations' rows by Euler's equation at
/// the new angular velocity.
struct PredictedInertia<'a> {
    model: &'a BeamModel,
    v: &'a [f64],
    a: &'a [f64],
    old: &'a [f64],
    out: &'a mut [f64],
}

impl hht::fast::Kernel for PredictedInertia<'_> {
    type Output = ();

    #[inline(always)]
    fn run<A: hht::fast::MulAdd>(self, _: A) {
        let plan = &self.model.inertia_plan;
        for unwritten in &plan.unwritten {
            self.out[unwritten.clone()].copy_from_slice(&self.old[unwritten.clone()]);
        }
        for run in &plan.runs {
            run.write_spin(self.v, self.a, self.old, self.out);
        }
    }
}

/// `x` as a slice: itself where contiguous (always, from the integrator), else a copy.
fn values(x: ColRef<'_, f64>) -> std::borrow::Cow<'_, [f64]> {
    match x.try_as_col_major() {
        Some(x) => std::borrow::Cow::Borrowed(x.as_slice()),
        None => std::borrow::Cow::Owned((0..x.nrows()).map(|i| x[i]).collect()),
    }
}

/// Runs `write` on `out` as a slice: itself where contiguous, else a copy written back.
fn write_to(mut out: ColMut<'_, f64>, write: impl FnOnce(&mut [f64])) {
    if let Some(out) = out.as_mut().try_as_col_major_mut() {
        return write(out.as_slice_mut());
    }
    let mut copy: Vec<f64> = (0..out.nrows()).map(|i| out[i]).collect();
    write(&mut copy);
    for (i, x) in copy.into_iter().enumerate() {
        out[i] = x;
    }
}

impl hht::Model for BeamModel {
    type Config = BeamState;

    fn ndof(&self) -> usize {
        self.ndof
    }

    fn update(&self, q: &mut BeamState, dq: ColRef<'_, f64>) {
        let dq = &*values(dq);
        for (node, (x, r)) in q.positions.iter_mut().zip(q.rotations.iter_mut()).enumerate() {
            (*x, *r) = self.displaced_node((&*x, &*r), dq, node);
        }
    }

    /// One pass over the nodes, writing `out` from `q` (no copy of `q` first).
    fn displaced(&self, q: &BeamState, dq: ColRef<'_, f64>, out: &mut BeamState) {
        let n = q.positions.len();
        out.positions.resize(n, Vector3::zeros());
        out.rotations.resize(n, UnitQuaternion::identity());
        hht::fast::run(Displace { model: self, q, dq: &values(dq), out });
    }

    fn inertial_force(
        &self,
        _q: &BeamState,
        v: ColRef<'_, f64>,
        a: ColRef<'_, f64>,
        out: ColMut<'_, f64>,
    ) {
        write_to(out, |out| self.inertial_force_into(&values(v), &values(a), out));
    }

    /// The translations' rows from `old` and the rotations' anew where every node with a
    /// free rotation is in a run (the usual mesh: the elements and point masses outside the
    /// runs add to translations only): a predictor's inertial force with only the rotations'
    /// arithmetic, the same bits (3.6 -> 2.3 % of the paper's tip in 3D). Otherwise the whole
    /// force.
    fn predicted_inertial_force(
        &self,
        q: &BeamState,
        v: ColRef<'_, f64>,
        a: ColRef<'_, f64>,
        old: ColRef<'_, f64>,
        out: ColMut<'_, f64>,
    ) {
        debug_assert_eq!(old.nrows(), self.ndof, "the old inertial force, one row an unknown");
        if !self.inertia_plan.rotations_in_runs {
            return self.inertial_force(q, v, a, out);
        }
        let (v, a, old) = (values(v), values(a), values(old));
        write_to(out, |out| {
            hht::fast::run(PredictedInertia { model: self, v: &v, a: &a, old: &old, out });
        });
    }

    fn net_force(&self, t: f64, q: &BeamState, _v: ColRef<'_, f64>, out: ColMut<'_, f64>) {
        write_to(out, |out| self.net_force_into(t, q, out, None));
    }

    fn tangent(
        &self,
        t: f64,
        q: &BeamState,
        v: ColRef<'_, f64>,
        _a: ColRef<'_, f64>,
        w: NewtonWeights,
        out: &mut Triplets,
    ) {
        let stiffness = w.force * w.dq;
        let mass = w.inertia * w.da;
        for e in &self.mesh.elements {
            let [na, nb] = e.nodes;
            let m = e.section.rho_a * e.length / 6.0 * mass;
            let nodes = [na, nb];
            if stiffness == 0.0 {
                // The mass alone (the eigen-solver's M, or a Newton matrix's change with the
                // step size) needs no element stiffness: only the translational mass's own
                // entries, the diagonals of the four displacement blocks (pushing the whole
                // 12 x 12 with zeros took 60 % of an event's re-weighted matrix in 3D).
                for (bi, &ni) in nodes.iter().enumerate() {
                    for (bj, &nj) in nodes.iter().enumerate() {
                        let factor = if bi == bj { 2.0 } else { 1.0 };
                        for c in 0..3 {
                            if let (Some(row), Some(col)) = (self.dofs[ni][c], self.dofs[nj][c]) {
                                out.push(row, col, m * factor);
                            }
                        }
                    }
                }
                continue;
            }
            let k = e
                .force_and_tangent(
                    [&q.positions[na], &q.positions[nb]],
                    [&q.rotations[na], &q.rotations[nb]],
                )
                .1;
            for (bi, &ni) in nodes.iter().enumerate() {
                for (bj, &nj) in nodes.iter().enumerate() {
                    for (oi, oj) in [(0, 0), (0, 3), (3, 0), (3, 3)] {
                        let mut block: Matrix3<f64> =
                            k.fixed_view::<3, 3>(6 * bi + oi, 6 * bj + oj).into_owned() * stiffness;
                        if oi == 0 && oj == 0 {
                            let factor = if bi == bj { 2.0 } else { 1.0 };
                            block += Matrix3::identity() * (m * factor);
                        }
                        self.push_block(out, ni, oi, nj, oj, &block);
                    }
                }
            }
        }
        // Rotary inertia with its gyroscopic derivative, and the load stiffness, per node.
        let mut node_blocks = vec![Matrix3::<f64>::zeros(); self.node_inertia.len()];
        let mut node_force_blocks = vec![Matrix3::<f64>::zeros(); self.node_inertia.len()];
        let v = values(v);
        for (node, j) in self.node_inertia.iter().enumerate() {
            let wv = self.node_vector(&v, node, 3);
            node_blocks[node] = j * mass + (skew(&wv) * j - skew(&(j * wv))) * (w.inertia * w.dv);
        }
        for load in &self.loads {
            let p = self.factor(t, load);
            let r = q.rotations[load.node];
            if load.follower {
                // d(R exp(th^) F)/dth = -R F^ ; the residual carries -f.
                let rm = r.to_rotation_matrix().into_inner();
                node_force_blocks[load.node] += rm * skew(&load.force) * (p * stiffness);
            } else {
                // d(exp(-th^) R^T M)/dth = (R^T M)^ ; the residual carries -m.
                node_blocks[load.node] -= skew(&(r.inverse() * load.moment)) * (p * stiffness);
            }
        }
        for node in 0..self.node_inertia.len() {
            self.push_block(out, node, 3, node, 3, &node_blocks[node]);
            if stiffness != 0.0 {
                self.push_block(out, node, 0, node, 3, &node_force_blocks[node]);
            }
        }
        for (node, m) in &self.point_masses {
            self.push_block(out, *node, 0, *node, 0, &(Matrix3::identity() * (m * mass)));
        }
        for (node, k) in &self.springs {
            self.push_block(out, *node, 0, *node, 0, &(Matrix3::from_diagonal(k) * stiffness));
        }
        for (node, k) in &self.rotational_springs {
            let j = crate::rotation::right_jacobian_inverse(&self.turned(q, *node));
            let block = j.transpose() * Matrix3::from_diagonal(k) * j * stiffness;
            self.push_block(out, *node, 3, *node, 3, &block);
        }
    }

    fn force_scale(&self, _q: &BeamState) -> f64 {
        self.force_scale
    }

    fn configuration_scale(&self, q: &BeamState) -> f64 {
        q.positions.iter().map(|x| x.amax()).fold(0.0, f64::max)
    }
}

/// Norm of the external loads at `q` and time `t` with the current load factor (N, N m).
pub(crate) fn load_norm(model: &BeamModel, t: f64, q: &BeamState) -> f64 {
    let mut total: f64 = 0.0;
    for load in &model.loads {
        let (f, m) = model.external(t, q, load);
        total += f.norm_squared() + m.norm_squared();
    }
    total.sqrt()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::{Material, Section};

    /// The inertial force element by element and node by node, as the equations read:
    /// `rho A l0 / 6 [2 1; 1 2]` on each direction of each element, `J dW/dt + W x J W` at
    /// each node with its full rotary inertia, `m a` for each point mass.
    fn inertial_force_by_definition(model: &BeamModel, v: &[f64], a: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; model.ndof];
        for e in &model.mesh.elements {
            let [na, nb] = e.nodes;
            let m = e.section.rho_a * e.length / 6.0;
            let (aa, ab) = (model.node_vector(a, na, 0), model.node_vector(a, nb, 0));
            model.add_node_vector(&mut out, na, 0, &((2.0 * aa + ab) * m));
            model.add_node_vector(&mut out, nb, 0, &((aa + 2.0 * ab) * m));
        }
        for (node, j) in model.node_inertia.iter().enumerate() {
            let (w, dw) = (model.node_vector(v, node, 3), model.node_vector(a, node, 3));
            model.add_node_vector(&mut out, node, 3, &(j * dw + w.cross(&(j * w))));
        }
        for (node, m) in &model.point_masses {
            model.add_node_vector(&mut out, *node, 0, &(model.node_vector(a, *node, 0) * *m));
        }
        out
    }

    #[test]
    fn the_inertia_plan_gives_the_inertial_force_by_definition() {
        // Meshes that take each path: one run of nodes (the usual), the same elements listed
        // last to first (runs of two nodes, the elements between them element by element), a
        // frame's corner with a node held in one direction mid-leg (three runs; the held node
        // and the corner's, its inertia not diagonal in its frame, by index) and point masses
        // with rotary inertia. The plan's sums are the definition's in another order: to round-off.
        let steel = Material::new(2.1e11, 0.3, 7850.0).unwrap();
        let section = Section::rectangle(&steel, 0.025, 0.005).unwrap();
        let straight = |from: Vector3<f64>, to: Vector3<f64>, n: usize| {
            Mesh::straight(from, to, n, section, Vector3::z()).unwrap()
        };
        let (o, x, xy) = (Vector3::zeros(), Vector3::x(), Vector3::new(1.0, 1.0, 0.0));
        let strip = BeamModel::new(straight(o, x, 20)).unwrap().support(0, Support::Clamped);
        let strip = strip.unwrap().attach_mass(20, 0.05, [1e-6, 2e-6, 3e-6]).unwrap();
        let mut reversed = straight(o, x, 20);
        reversed.elements.reverse();
        let reversed = BeamModel::new(reversed).unwrap().support(0, Support::Clamped).unwrap();
        let frame = straight(o, x, 12).join(straight(x, xy, 9)).unwrap();
        let frame = BeamModel::new(frame).unwrap().support(0, Support::Clamped).unwrap();
        let frame = frame.hold(&[(6, 1)]).unwrap().attach_mass(6, 0.2, [0.0, 1e-5, 0.0]).unwrap();
        let mut seed = 11_u64;
        let mut noise = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (seed >> 11) as f64 / (1_u64 << 53) as f64 - 0.5
        };
        for (model, runs) in [(&strip, 1), (&reversed, 10), (&frame, 3)] {
            assert_eq!(model.inertia_plan.runs.len(), runs);
            let v: Vec<f64> = (0..model.ndof).map(|_| 30.0 * noise()).collect();
            let a: Vec<f64> = (0..model.ndof).map(|_| 1e5 * noise()).collect();
            let expected = inertial_force_by_definition(model, &v, &a);
            let mut out = vec![f64::NAN; model.ndof];
            model.inertial_force_into(&v, &a, &mut out);
            let scale = expected.iter().fold(0.0_f64, |m, f| m.max(f.abs()));
            for (i, (f, e)) in out.iter().zip(&expected).enumerate() {
                assert!((f - e).abs() <= 1e-14 * scale, "unknown {i}: {f} against {e}");
            }
            // And the kinetic energy through the same plan: v . I(v, v) / 2 (the gyroscopic
            // term is normal to W).
            let mut i = vec![0.0; model.ndof];
            model.inertial_force_into(&v, &v, &mut i);
            let two_t: f64 = v.iter().zip(&i).map(|(v, i)| v * i).sum();
            let kinetic = model.kinetic_energy(ColRef::from_slice(&v));
            assert!((2.0 * kinetic - two_t).abs() <= 1e-13 * two_t);
            // A predictor's inertial force, from the old one at the same acceleration: the
            // whole force's bits at the new velocity (the translations' rows copied, the
            // rotations' computed; where a free rotation is outside the runs, the whole force).
            let v_new: Vec<f64> = (0..model.ndof).map(|_| 30.0 * noise()).collect();
            let mut old = vec![0.0; model.ndof];
            model.inertial_force_into(&v, &a, &mut old);
            let mut whole = vec![0.0; model.ndof];
            model.inertial_force_into(&v_new, &a, &mut whole);
            let mut predicted = faer::Col::<f64>::from_fn(model.ndof, |_| f64::NAN);
            let (v_new, a) = (ColRef::from_slice(&v_new), ColRef::from_slice(&a));
            let (q, old_force) = (model.reference_state(), ColRef::from_slice(&old));
            hht::Model::predicted_inertial_force(
                model,
                &q,
                v_new,
                a,
                old_force,
                predicted.as_mut(),
            );
            let bits = |x: &[f64]| x.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
            let predicted: Vec<f64> = predicted.iter().copied().collect();
            assert_eq!(bits(&predicted), bits(&whole));
            assert_ne!(bits(&old), bits(&whole));
        }
        // The strip and the reversed one take the copy, the frame (its corner's inertia not
        // diagonal in its frame) the whole force.
        let taken = [&strip, &reversed, &frame].map(|m| m.inertia_plan.rotations_in_runs);
        assert_eq!(taken, [true, true, false]);
    }
}
