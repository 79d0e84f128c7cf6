//! Geometry of the undeformed beam: nodes with their section frames, and the elements.

use crate::element::Element;
use crate::error::{positive, BeamError};
use crate::section::Section;
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

/// Nodes (positions and section frames) and elements of an undeformed beam.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// Reference node positions (m).
    pub positions: Vec<Vector3<f64>>,
    /// Reference section frames: each maps (E1 along the axis, E2, E3) to space.
    pub frames: Vec<UnitQuaternion<f64>>,
    /// Elements.
    pub elements: Vec<Element>,
    /// Arc length of each node from the first (m), along the reference axis.
    pub arc_length: Vec<f64>,
}

fn frame(tangent: &Vector3<f64>, e3_hint: &Vector3<f64>) -> Result<UnitQuaternion<f64>, BeamError> {
    let e1 = tangent.normalize();
    let e2 = e3_hint.cross(&e1);
    // Written so that a hint or tangent that is not a number is refused too (a NaN hint had
    // given NaN frames, a review's).
    if e2.norm().is_nan() || e2.norm() < 1e-9 {
        return Err(BeamError::Mesh(format!(
            "the section axis E3 hint {e3_hint:?} is parallel to the beam axis {e1:?}"
        )));
    }
    let e2 = e2.normalize();
    let e3 = e1.cross(&e2);
    let m = Matrix3::from_columns(&[e1, e2, e3]);
    Ok(UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m)))
}

impl Mesh {
    /// A straight beam from `start` to `end` (m) in `elements` equal elements. The section axis
    /// E3 is the part of `e3_hint` normal to the axis (for a rectangle: the thickness direction,
    /// so bending about E2 with `I2 = w t^3 / 12` deflects along E3).
    ///
    /// # Errors
    /// [`BeamError::Mesh`] for a zero length, no elements, or a hint along the axis.
    pub fn straight(
        start: Vector3<f64>,
        end: Vector3<f64>,
        elements: usize,
        section: Section,
        e3_hint: Vector3<f64>,
    ) -> Result<Self, BeamError> {
        if elements == 0 {
            return Err(BeamError::Mesh("a beam needs at least one element".into()));
        }
        let fractions: Vec<f64> = (0..=elements).map(|i| i as f64 / elements as f64).collect();
        Self::straight_through(start, end, &fractions, section, e3_hint)
    }

    /// [`Mesh::straight`] with its nodes at `fractions` of the way from `start` to `end`
    /// (increasing, from 0 to 1: a graded mesh).
    ///
    /// # Errors
    /// [`BeamError::Mesh`] for fewer than two fractions or fractions that do not rise from 0
    /// to 1, and as [`Mesh::straight`].
    pub fn straight_through(
        start: Vector3<f64>,
        end: Vector3<f64>,
        fractions: &[f64],
        section: Section,
        e3_hint: Vector3<f64>,
    ) -> Result<Self, BeamError> {
        let axis = end - start;
        positive("beam length", axis.norm())?;
        let rising = fractions.windows(2).all(|w| w[0] < w[1]);
        if !(fractions.len() >= 2
            && rising
            && fractions[0] == 0.0
            && fractions.last() == Some(&1.0))
        {
            return Err(BeamError::Mesh(format!("a straight piece's nodes at fractions of its length need at least two values rising from 0 to 1, not {fractions:?}")));
        }
        let q = frame(&axis, &e3_hint)?;
        let positions: Vec<_> = fractions.iter().map(|f| start + axis * *f).collect();
        Self::from_nodes(positions, vec![q; fractions.len()], section)
    }

    /// A circular arc in the plane normal to `normal` (E3 of every section), centred at
    /// `centre`, of `radius` (m), starting at the point `centre + radius * start_direction` and
    /// sweeping `angle` (rad, right-handed about `normal`), in `elements` equal elements.
    ///
    /// # Errors
    /// [`BeamError::Mesh`] or [`BeamError::InvalidParameter`] for degenerate input.
    pub fn arc(
        centre: Vector3<f64>,
        radius: f64,
        start_direction: Vector3<f64>,
        normal: Vector3<f64>,
        angle: f64,
        elements: usize,
        section: Section,
    ) -> Result<Self, BeamError> {
        positive("arc radius", radius)?;
        positive("arc angle", angle.abs())?;
        if elements == 0 {
            return Err(BeamError::Mesh("a beam needs at least one element".into()));
        }
        // A zero or non-finite normal, or a start along it, has no plane: refused (they had
        // given NaN positions, a review's).
        if !(normal.norm() > 0.0 && normal.iter().all(|c| c.is_finite())) {
            return Err(BeamError::Mesh(format!("the arc's normal {normal:?} has no direction")));
        }
        let n = normal.normalize();
        let in_plane = start_direction - n * n.dot(&start_direction);
        if in_plane.norm().is_nan() || in_plane.norm() <= 1e-9 * start_direction.norm() {
            return Err(BeamError::Mesh(format!(
                "the arc's start direction {start_direction:?} has no part normal to its normal {normal:?}"
            )));
        }
        let u = in_plane.normalize();
        let w = n.cross(&u);
        let mut positions = Vec::new();
        let mut frames = Vec::new();
        for i in 0..=elements {
            let t = angle * i as f64 / elements as f64;
            positions.push(centre + (u * t.cos() + w * t.sin()) * radius);
            let tangent = (-u * t.sin() + w * t.cos()) * angle.signum();
            frames.push(frame(&tangent, &n)?);
        }
        Self::from_nodes(positions, frames, section)
    }

    /// Chains the nodes in order with one section.
    ///
    /// # Errors
    /// [`BeamError::Mesh`] for fewer than two nodes, a frame count that is not the node count,
    /// a position or frame that is not a number, or two neighbouring nodes at one place (a
    /// zero-length element); [`BeamError::InvalidParameter`] for a section that is not
    /// physical ([`Section::validated`]). (The mesh had panicked on fewer frames than nodes,
    /// and a zero-length element had failed only in a solve, as a residual not finite, a
    /// review's.)
    pub fn from_nodes(
        positions: Vec<Vector3<f64>>,
        frames: Vec<UnitQuaternion<f64>>,
        section: Section,
    ) -> Result<Self, BeamError> {
        let section = section.validated()?;
        if positions.len() < 2 || frames.len() != positions.len() {
            return Err(BeamError::Mesh(format!(
                "a mesh needs at least two nodes and one frame a node, not {} nodes and {} frames",
                positions.len(),
                frames.len()
            )));
        }
        let finite = |v: &[f64]| v.iter().all(|c| c.is_finite());
        if let Some(k) = (0..positions.len())
            .find(|&k| !(finite(positions[k].as_slice()) && finite(frames[k].coords.as_slice())))
        {
            return Err(BeamError::Mesh(format!("node {k}'s position or frame is not a number")));
        }
        if let Some(k) =
            (1..positions.len()).find(|&k| (positions[k] - positions[k - 1]).norm() <= 0.0)
        {
            return Err(BeamError::Mesh(format!(
                "nodes {} and {k} are at one place: an element needs a length",
                k - 1
            )));
        }
        let mut elements = Vec::new();
        let mut arc_length = vec![0.0];
        for i in 0..positions.len().saturating_sub(1) {
            let e = Element::new(
                [i, i + 1],
                section,
                [&positions[i], &positions[i + 1]],
                [&frames[i], &frames[i + 1]],
            );
            arc_length.push(arc_length[i] + e.length);
            elements.push(e);
        }
        Ok(Self { positions, frames, elements, arc_length })
    }

    /// Appends another mesh whose first node coincides with this mesh's last node (a frame
    /// corner, for example); the shared node keeps this mesh's frame, so the corner is rigid.
    ///
    /// # Errors
    /// [`BeamError::Mesh`] if the two ends are more than 1e-9 m apart.
    pub fn join(mut self, other: Mesh) -> Result<Self, BeamError> {
        let (Some(last), Some(first)) = (self.positions.last(), other.positions.first()) else {
            return Err(BeamError::Mesh("cannot join an empty mesh".into()));
        };
        if (last - first).norm() > 1e-9 {
            return Err(BeamError::Mesh(format!("meshes do not meet: {last:?} vs {first:?}")));
        }
        let offset = self.positions.len() - 1;
        let s0 = self.arc_length[offset];
        for mut e in other.elements {
            // Elements touching the shared node keep their own end frame through a constant
            // offset from the node's frame (rigid corner).
            for end in 0..2 {
                if e.nodes[end] == 0 {
                    e.offsets[end] =
                        self.frames[offset].inverse() * other.frames[0] * e.offsets[end];
                }
            }
            e.nodes = [e.nodes[0] + offset, e.nodes[1] + offset];
            self.elements.push(e);
        }
        for i in 1..other.positions.len() {
            self.positions.push(other.positions[i]);
            self.frames.push(other.frames[i]);
            self.arc_length.push(s0 + other.arc_length[i]);
        }
        Ok(self)
    }

    /// Index of the node nearest to arc length `s` (m).
    pub fn node_at(&self, s: f64) -> usize {
        let mut best = 0;
        for (i, &si) in self.arc_length.iter().enumerate() {
            if (si - s).abs() < (self.arc_length[best] - s).abs() {
                best = i;
            }
        }
        best
    }
}
