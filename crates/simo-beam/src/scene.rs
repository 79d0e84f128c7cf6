//! A beam-only scene: the Simo beam under prescribed loads (no ball), static or dynamic.
//!
//! This is how a user runs the standard beam benchmarks (Mattiasson, the 45-degree bend, the
//! right-angle cantilever) or their own frame without writing Rust:
//!
//! ```toml
//! name = "mattiasson-k10"
//! analysis = "static"            # static | dynamic
//! [section]                      # a material and a shape, or the stiffnesses directly
//! axial_stiffness = 1e7          # EA (N)
//! shear_stiffness = 1e7          # k G A (N), both shear directions
//! torsional_stiffness = 1.0      # G J (N m^2)
//! bending_stiffness = 1.0        # E I (N m^2), both bending directions
//! [[segment]]                    # straight or arc pieces, chained with rigid corners
//! start = [0.0, 0.0, 0.0]
//! end = [1.0, 0.0, 0.0]
//! elements = 64
//! [[support]]
//! at = 0.0                       # arc length (m) of a node
//! kind = "clamped"               # clamped | pinned
//! [[load]]
//! at = 1.0                       # arc length (m)
//! force = [0.0, 0.0, -10.0]      # (N), spatial (or in the section frame if follower)
//! [static]
//! load_steps = 10
//! ```
//!
//! A dynamic scene replaces `[static]` by `[dynamic]` (`duration`, `time_step` in s, optional
//! HHT `alpha` in [-1/3, 0]) and may give each load a `profile` of (time (s), factor) points,
//! linear between them and held beyond their ends: before its first point the first factor
//! holds from t = 0 (a run warns where that factor is not 0; start with `[0.0, 0.0]` for a
//! load that comes later). A run warns where a strain passes the small-strain range of the
//! linear section law ([`SMALL_STRAIN`]).

use crate::{
    solve_static, BeamError, BeamModel, BeamState, Load, Material, Mesh, Profile, Section,
    StaticOptions, Support,
};
use faer::Col;
use hht::{Integrator, Model, NewtonOptions, Scheme};
use nalgebra::{UnitQuaternion, Vector3};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// What can go wrong when reading or running a beam scene.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The file is not valid TOML or does not match the scene's keys (unknown key, missing
    /// field, wrong type); the message names the key and the line.
    #[error("beam scene file: {0}")]
    Parse(String),
    /// A field has a value outside what is allowed.
    #[error("{field} = {value}: {allowed}")]
    InvalidField {
        /// Dotted path of the field as written in the file, e.g. `segment[0].elements`.
        field: String,
        /// The value as written.
        value: String,
        /// What would be accepted, with the unit.
        allowed: String,
    },
    /// A combination of fields that does not make a beam scene.
    #[error("{0}")]
    Inconsistent(String),
    /// The beam crate refused the model the scene describes.
    #[error(transparent)]
    Beam(#[from] BeamError),
    /// The static analysis could not reach the full load.
    #[error("the static analysis stopped at load factor {load_factor}")]
    StaticFailed {
        /// Fraction of the load reached (-).
        load_factor: f64,
        /// Why the last load step failed.
        #[source]
        source: BeamError,
    },
    /// The stiffness matrix is singular: the supports leave the beam free to move as a rigid
    /// body (one pinned support, or none) or the loaded shape is a mechanism.
    #[error("the beam is a mechanism at load factor {load_factor}: its stiffness matrix is singular; the supports must hold it (clamp a node, or pin points not all on one line; pins on one straight line leave the turn about that line free, which a forked support (a pin that holds the twist) holds)")]
    Mechanism {
        /// Fraction of the load reached (-).
        load_factor: f64,
    },
    /// The time integration failed.
    #[error("the dynamic analysis failed at t = {t} s")]
    DynamicFailed {
        /// Simulated time reached (s).
        t: f64,
        /// What the integrator reported.
        #[source]
        source: hht::HhtError,
    },
}

/// The most elements a piece of a beam scene may have.
const MAX_ELEMENTS: usize = 100_000;
/// The most load steps of a static analysis (each is a Newton solve).
const MAX_LOAD_STEPS: usize = 1_000_000;

/// A number as a user reads it: in scientific notation when very large or small.
fn show(value: f64) -> String {
    let size = value.abs();
    if size != 0.0 && !(1e-4..1e6).contains(&size) && size.is_finite() {
        format!("{value:e}")
    } else {
        value.to_string()
    }
}

/// A TOML reader's message with the Rust and serde type names a scene file's author does not
/// write (`usize`, `f64`, `i128`, a sequence, a map) put in TOML's words.
pub fn toml_message(error: &toml::de::Error) -> String {
    const WORDS: [(&str, &str); 8] = [
        (" as i128,", " (more than 64 bits),"),
        ("expected usize", "expected a whole number (a count)"),
        ("expected u64", "expected a whole number (a count)"),
        ("expected f64", "expected a number"),
        ("invalid type: sequence,", "invalid type: an array,"),
        ("expected a sequence", "expected an array"),
        ("invalid type: map,", "invalid type: a table,"),
        ("expected a map", "expected a table"),
    ];
    WORDS.iter().fold(error.to_string(), |m, (rust, words)| m.replace(rust, words))
}

/// A point or direction as a scene file writes it, `[x, y, z]`.
fn point(v: &Vector3<f64>) -> String {
    format!("[{}, {}, {}]", show(v.x), show(v.y), show(v.z))
}

/// `value` to 4 significant digits (a derived length in a message).
fn round4(value: f64) -> f64 {
    format!("{value:.3e}").parse().unwrap_or(value)
}

/// `field` must be finite and strictly positive.
fn positive(field: &str, value: f64, unit: &str) -> Result<f64, SceneError> {
    if !(value.is_finite() && value > 0.0) {
        return Err(SceneError::InvalidField {
            field: field.to_owned(),
            value: show(value),
            allowed: format!("must be a finite number greater than 0 ({unit})"),
        });
    }
    Ok(value)
}

/// The JSON Schema (draft 2020-12) of a TOML file read as `T`, titled `title`: an optional
/// key is left out, never `null` (TOML has none), and a table's default is not spelled out
/// as an object (its keys carry their own defaults).
pub fn toml_schema<T: JsonSchema>(title: &str) -> schemars::Schema {
    let tables = schemars::transform::RecursiveTransform(|schema: &mut schemars::Schema| {
        if schema.get("default").is_some_and(|d| d.is_object()) {
            schema.remove("default");
        }
        without_null(schema);
    });
    let mut schema = schemars::generate::SchemaSettings::draft2020_12()
        .with_transform(tables)
        .into_generator()
        .into_root_schema_for::<T>();
    schema.insert("title".into(), title.into());
    schema
}

/// An `Option` field's schema without its `null` (`"type": ["number", "null"]`, or `anyOf` a
/// reference and `null`): a TOML file leaves the key out instead.
fn without_null(schema: &mut schemars::Schema) {
    use serde_json::Value;
    let null = |v: &Value| v.get("type").and_then(Value::as_str) == Some("null");
    if let Some(Value::Array(types)) = schema.get_mut("type") {
        types.retain(|t| t.as_str() != Some("null"));
        if types.len() == 1 {
            let only = types.remove(0);
            schema.insert("type".into(), only);
        }
    }
    let Some(Value::Array(any)) = schema.get_mut("anyOf") else { return };
    if any.len() == 2 && any.iter().any(null) {
        any.retain(|v| !null(v));
        let Some(Value::Object(kept)) = any.pop() else { return };
        schema.remove("anyOf");
        for (k, v) in kept {
            schema.insert(k, v);
        }
    }
}

/// Static or dynamic analysis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum AnalysisName {
    /// Equilibrium under the full loads, reached in load steps.
    Static,
    /// Motion from rest under time-varying loads, integrated by HHT-alpha.
    Dynamic,
}

/// A beam under prescribed loads. Every unknown key is an error.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BeamScene {
    /// Name used in reports and file names.
    pub name: String,
    /// Static or dynamic.
    pub analysis: AnalysisName,
    /// The cross-section, the same along the whole beam.
    pub section: SectionSpec,
    /// The pieces of the beam axis, in order (at least one).
    #[serde(rename = "segment")]
    pub segments: Vec<SegmentSpec>,
    /// Supports at nodes.
    #[serde(rename = "support", default)]
    pub supports: Vec<SupportSpec>,
    /// Point loads.
    #[serde(rename = "load", default)]
    pub loads: Vec<LoadSpec>,
    /// Settings of a static analysis.
    #[serde(rename = "static")]
    pub statics: Option<StaticSpec>,
    /// Settings of a dynamic analysis (required when `analysis = "dynamic"`).
    pub dynamic: Option<DynamicSpec>,
    /// Which point the history follows.
    #[serde(default)]
    pub output: OutputSpec,
}

/// A section: either a material (`youngs_modulus`, `poisson_ratio`, `density`) with a rectangle
/// (`width`, `thickness`) or a circle (`radius`), or the stiffnesses directly.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SectionSpec {
    /// Young's modulus E (Pa).
    #[schemars(extend("exclusiveMinimum" = 0), extend("x-unit" = "Pa"))]
    pub youngs_modulus: Option<f64>,
    /// Poisson's ratio (-).
    #[schemars(extend("exclusiveMinimum" = -1, "exclusiveMaximum" = 0.5))]
    pub poisson_ratio: Option<f64>,
    /// Density (kg/m^3).
    #[schemars(extend("exclusiveMinimum" = 0), extend("x-unit" = "kg/m^3"))]
    pub density: Option<f64>,
    /// Rectangle width along the section axis E2 (m).
    #[schemars(extend("exclusiveMinimum" = 0), extend("x-unit" = "m"))]
    pub width: Option<f64>,
    /// Rectangle thickness along the section axis E3 (m).
    #[schemars(extend("exclusiveMinimum" = 0), extend("x-unit" = "m"))]
    pub thickness: Option<f64>,
    /// Circle radius (m).
    #[schemars(extend("exclusiveMinimum" = 0), extend("x-unit" = "m"))]
    pub radius: Option<f64>,
    /// EA (N).
    #[schemars(extend("exclusiveMinimum" = 0), extend("x-unit" = "N"))]
    pub axial_stiffness: Option<f64>,
    /// k G A (N), both shear directions.
    #[schemars(extend("exclusiveMinimum" = 0), extend("x-unit" = "N"))]
    pub shear_stiffness: Option<f64>,
    /// G J (N m^2).
    #[schemars(extend("exclusiveMinimum" = 0), extend("x-unit" = "N m^2"))]
    pub torsional_stiffness: Option<f64>,
    /// E I (N m^2) about both section axes, unless `bending_stiffness_2`/`_3` are given.
    #[schemars(extend("exclusiveMinimum" = 0), extend("x-unit" = "N m^2"))]
    pub bending_stiffness: Option<f64>,
    /// E I2 about E2 (N m^2).
    #[schemars(extend("exclusiveMinimum" = 0), extend("x-unit" = "N m^2"))]
    pub bending_stiffness_2: Option<f64>,
    /// E I3 about E3 (N m^2).
    #[schemars(extend("exclusiveMinimum" = 0), extend("x-unit" = "N m^2"))]
    pub bending_stiffness_3: Option<f64>,
    /// rho A (kg/m); default 1 (statics does not use it).
    #[schemars(extend("exclusiveMinimum" = 0), extend("x-unit" = "kg/m"))]
    pub mass_per_length: Option<f64>,
    /// rho (I2 + I3), rho I2, rho I3 (kg m); default 1e-3 x `mass_per_length` each.
    #[schemars(extend("x-unit" = "kg m"))]
    #[serde(default, deserialize_with = "exactly_some")]
    pub rotary_inertia: Option<[f64; 3]>,
}

/// Exactly `N` numbers (a scene's vector), for `#[serde(deserialize_with)]`: serde's arrays
/// read the first `N` items of a longer TOML array and drop the rest (a review's
/// `end = [0.5, 0.5, 0.0, "junk"]` ran as its first three).
pub fn exactly<'de, D: serde::Deserializer<'de>, const N: usize>(
    d: D,
) -> Result<[f64; N], D::Error> {
    let numbers = Vec::<f64>::deserialize(d)?;
    numbers.as_slice().try_into().map_err(|_| {
        serde::de::Error::invalid_length(
            numbers.len(),
            &format!("an array of {N} numbers").as_str(),
        )
    })
}

/// [`exactly`] for an optional key (with `#[serde(default)]` for its absence).
pub fn exactly_some<'de, D: serde::Deserializer<'de>, const N: usize>(
    d: D,
) -> Result<Option<[f64; N]>, D::Error> {
    exactly(d).map(Some)
}

/// A profile's `[time, factor]` points, each exactly two numbers (see [`exactly`]).
fn pairs<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<Vec<[f64; 2]>>, D::Error> {
    let points = Vec::<Vec<f64>>::deserialize(d)?;
    let pair = |p: &Vec<f64>| {
        p.as_slice().try_into().map_err(|_| {
            serde::de::Error::invalid_length(p.len(), &"a point of two numbers, [time, factor]")
        })
    };
    points.iter().map(pair).collect::<Result<Vec<_>, _>>().map(Some)
}

/// One piece of the beam axis. It starts where the previous piece ended (the first at `start`,
/// default the origin); a straight piece goes to `end`, an arc turns `angle_degrees` about
/// `normal` around `centre`. Pieces meet rigidly at any angle, except one that folds back so
/// sharply onto the piece before that the two members would lie inside each other beyond the
/// shorter one's length (sections of half depth c meeting at phi overlap over c/tan(phi/2)).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SegmentSpec {
    /// Start point (m); only needed for the first piece (later pieces must start where the
    /// previous ended, if given).
    #[schemars(extend("x-unit" = "m"))]
    #[serde(default, deserialize_with = "exactly_some")]
    pub start: Option<[f64; 3]>,
    /// End point of a straight piece (m).
    #[schemars(extend("x-unit" = "m"))]
    #[serde(default, deserialize_with = "exactly_some")]
    pub end: Option<[f64; 3]>,
    /// Centre of an arc (m).
    #[schemars(extend("x-unit" = "m"))]
    #[serde(default, deserialize_with = "exactly_some")]
    pub centre: Option<[f64; 3]>,
    /// Axis of an arc (right-handed turn); it is also the section axis E3 along the arc.
    #[serde(default, deserialize_with = "exactly_some")]
    pub normal: Option<[f64; 3]>,
    /// Angle swept by an arc (degrees).
    #[schemars(extend("x-unit" = "deg"))]
    pub angle_degrees: Option<f64>,
    /// Section axis E3 (thickness direction) of a straight piece; default z, or x for a piece
    /// along z. A direction not perpendicular to the piece gives E3 its perpendicular part
    /// (its component along the piece is dropped); one along the piece is refused.
    #[serde(default, deserialize_with = "exactly_some")]
    pub thickness_direction: Option<[f64; 3]>,
    /// Number of elements.
    #[schemars(range(min = 1, max = 100_000))]
    pub elements: usize,
    /// The segment's own section (a stepped member), in place of the scene's `[section]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub section: Option<SectionSpec>,
    /// The nodes' places along a straight piece, as fractions of its length (`elements + 1`
    /// values rising from 0 to 1); equally spaced when `None`. Not read from a scene file: set
    /// where another description lowers onto this one (an impact scene's `[beam]` on its
    /// graded mesh).
    #[serde(skip)]
    #[schemars(skip)]
    pub nodes: Option<Vec<f64>>,
}

/// A support at the node at arc length `at`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SupportSpec {
    /// Arc length from the start of the first piece (m); must be a node.
    #[schemars(range(min = 0), extend("x-unit" = "m"))]
    pub at: f64,
    /// Clamped, pinned or forked.
    pub kind: Support,
}

/// A point load at arc length `at`, shared between the two nodes of its element.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LoadSpec {
    /// Arc length from the start (m).
    #[schemars(range(min = 0), extend("x-unit" = "m"))]
    pub at: f64,
    /// Force (N).
    #[serde(default, deserialize_with = "exactly")]
    #[schemars(extend("x-unit" = "N"))]
    pub force: [f64; 3],
    /// Moment (N m).
    #[serde(default, deserialize_with = "exactly")]
    #[schemars(extend("x-unit" = "N m"))]
    pub moment: [f64; 3],
    /// Whether the load turns with the section (given in the section frame E1, E2, E3).
    #[serde(default)]
    pub follower: bool,
    /// Dynamic analysis: (time (s), factor) points, piecewise linear, constant beyond the
    /// ends (before the first point's time its factor holds, from t = 0); default factor 1 at
    /// all times. A static analysis refuses it (its loads grow with the load factor).
    #[serde(default, deserialize_with = "pairs")]
    #[schemars(extend("x-unit" = "s, -"))]
    pub profile: Option<Vec<[f64; 2]>>,
}

/// Static analysis settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StaticSpec {
    /// Equal load increments (each cut in half automatically if Newton fails); default 10.
    #[schemars(range(min = 1, max = 1_000_000))]
    pub load_steps: Option<usize>,
}

/// Dynamic analysis settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DynamicSpec {
    /// Simulated time (s) from rest in the reference configuration.
    #[schemars(extend("exclusiveMinimum" = 0), extend("x-unit" = "s"))]
    pub duration: f64,
    /// Time step (s).
    #[schemars(extend("exclusiveMinimum" = 0), extend("x-unit" = "s"))]
    pub time_step: f64,
    /// HHT alpha in [-1/3, 0]; default 0 (trapezoidal rule, no numerical damping).
    #[schemars(range(min = -0.333_333_333_333_333_3, max = 0))]
    pub alpha: Option<f64>,
}

/// Output settings.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Arc length (m) of the node whose history is recorded; default the last node.
    #[schemars(range(min = 0), extend("x-unit" = "m"))]
    pub track: Option<f64>,
}

/// One sample of the tracked node.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TrackSample {
    /// Time (s) in dynamics, load factor (-) in statics.
    pub time_or_load: f64,
    /// Position (m).
    pub position: [f64; 3],
    /// Rotation of the section from its reference orientation, as a rotation vector (rad),
    /// spatial components.
    pub rotation: [f64; 3],
    /// Strain energy (J).
    pub strain_energy: f64,
    /// Kinetic energy (J); zero in statics.
    pub kinetic_energy: f64,
}

/// One node of the final configuration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ShapeNode {
    /// Reference arc length (m).
    pub arc_length: f64,
    /// Position (m).
    pub position: [f64; 3],
    /// Rotation from the reference orientation as a rotation vector (rad).
    pub rotation: [f64; 3],
}

/// The result of a beam scene.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BeamRun {
    /// Scene name.
    pub name: String,
    /// Arc length (m) of the tracked node.
    pub tracked_arc_length: f64,
    /// Static (the history's first column a load factor) or dynamic (a time).
    pub analysis: AnalysisName,
    /// History of the tracked node.
    pub history: Vec<TrackSample>,
    /// The final configuration.
    pub shape: Vec<ShapeNode>,
    /// Number of unknowns.
    pub unknowns: usize,
    /// Newton iterations in total.
    pub newton_iterations: usize,
    /// Load increments cut (statics) or time steps halved (dynamics).
    pub cuts: usize,
    /// Wall-clock time of the solve (s).
    pub wall_time: f64,
    /// What the result leaves out: strains beyond the small-strain range of the linear
    /// section law ([`SMALL_STRAIN`]), with their size and where on the path they occur.
    pub warnings: Vec<String>,
}

/// The largest axial or shear strain the linear elastic section law is meant for (-): beyond
/// a per cent a metal yields and the law's straight line is no longer the material.
pub const SMALL_STRAIN: f64 = 0.01;

/// The shortest straight segment (m): a nanometre, as the impact scenes' shortest length.
const MIN_SEGMENT: f64 = 1e-9;

fn invalid(field: String, value: impl ToString, allowed: &str) -> SceneError {
    SceneError::InvalidField { field, value: value.to_string(), allowed: allowed.to_owned() }
}

fn vector(field: &str, v: [f64; 3]) -> Result<Vector3<f64>, SceneError> {
    if v.iter().any(|x| !x.is_finite()) {
        return Err(invalid(field.to_owned(), format!("{v:?}"), "three finite numbers"));
    }
    Ok(Vector3::from(v))
}

fn direction(field: &str, v: [f64; 3]) -> Result<Vector3<f64>, SceneError> {
    let d = vector(field, v)?;
    if d.norm() == 0.0 {
        return Err(invalid(field.to_owned(), format!("{v:?}"), "a non-zero direction"));
    }
    Ok(d)
}

impl SectionSpec {
    fn build(&self) -> Result<Section, SceneError> {
        let material_form = self.youngs_modulus.is_some()
            || self.poisson_ratio.is_some()
            || self.width.is_some()
            || self.thickness.is_some()
            || self.radius.is_some();
        let stiffness_form = self.axial_stiffness.is_some()
            || self.shear_stiffness.is_some()
            || self.torsional_stiffness.is_some()
            || self.bending_stiffness.is_some()
            || self.bending_stiffness_2.is_some()
            || self.bending_stiffness_3.is_some();
        let need = |name: &str, v: Option<f64>| {
            v.ok_or_else(|| {
                SceneError::Inconsistent(format!("section.{name} is missing (a number is needed)"))
            })
        };
        match (material_form, stiffness_form) {
            (true, true) => Err(SceneError::Inconsistent(
                "section: give either a material and a shape (youngs_modulus, poisson_ratio, \
                 density, width and thickness or radius) or the stiffnesses (axial_stiffness, \
                 shear_stiffness, torsional_stiffness, bending_stiffness), not both"
                    .into(),
            )),
            (false, false) => Err(SceneError::Inconsistent(
                "section is empty: give a material and a shape or the stiffnesses".into(),
            )),
            (true, false) => {
                let e = need("youngs_modulus", self.youngs_modulus)?;
                let nu = need("poisson_ratio", self.poisson_ratio)?;
                let rho = need("density", self.density)?;
                positive("section.youngs_modulus", e, "Pa")?;
                positive("section.density", rho, "kg/m^3")?;
                if self.mass_per_length.is_some() || self.rotary_inertia.is_some() {
                    return Err(SceneError::Inconsistent(
                        "section: mass_per_length and rotary_inertia come from the density and \
                         the shape; remove them"
                            .into(),
                    ));
                }
                if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
                    return Err(invalid(
                        "section.poisson_ratio".into(),
                        nu,
                        "a number in (-1, 0.5)",
                    ));
                }
                let material = Material::new(e, nu, rho)?;
                match (self.width, self.thickness, self.radius) {
                    (Some(w), Some(t), None) => {
                        positive("section.width", w, "m")?;
                        positive("section.thickness", t, "m")?;
                        Ok(Section::rectangle(&material, w, t)?)
                    }
                    (None, None, Some(r)) => {
                        positive("section.radius", r, "m")?;
                        Ok(Section::circle(&material, r)?)
                    }
                    _ => Err(SceneError::Inconsistent(
                        "section: give width and thickness (rectangle) or radius (circle)".into(),
                    )),
                }
            }
            (false, true) => {
                if self.density.is_some() {
                    return Err(SceneError::Inconsistent(
                        "section: with stiffnesses, give mass_per_length and rotary_inertia \
                         instead of density"
                            .into(),
                    ));
                }
                let ea = positive(
                    "section.axial_stiffness",
                    need("axial_stiffness", self.axial_stiffness)?,
                    "N",
                )?;
                let ga = positive(
                    "section.shear_stiffness",
                    need("shear_stiffness", self.shear_stiffness)?,
                    "N",
                )?;
                let gj = positive(
                    "section.torsional_stiffness",
                    need("torsional_stiffness", self.torsional_stiffness)?,
                    "N m^2",
                )?;
                // The error names the key the file holds: the axis's own, or the shared one.
                let bending = |name: &str, own: Option<f64>| match (own, self.bending_stiffness) {
                    (Some(v), _) => positive(&format!("section.{name}"), v, "N m^2"),
                    (None, Some(v)) => positive("section.bending_stiffness", v, "N m^2"),
                    (None, None) => Err(SceneError::Inconsistent(format!(
                        "section.{name} is missing (or give bending_stiffness for both axes)"
                    ))),
                };
                let ei2 = bending("bending_stiffness_2", self.bending_stiffness_2)?;
                let ei3 = bending("bending_stiffness_3", self.bending_stiffness_3)?;
                let rho_a = positive(
                    "section.mass_per_length",
                    self.mass_per_length.unwrap_or(1.0),
                    "kg/m",
                )?;
                let rho_i = self.rotary_inertia.unwrap_or([1e-3 * rho_a; 3]);
                for (k, r) in rho_i.iter().enumerate() {
                    positive(&format!("section.rotary_inertia[{k}]"), *r, "kg m")?;
                }
                Ok(Section { ea, ga2: ga, ga3: ga, gj, ei2, ei3, rho_a, rho_i }.validated()?)
            }
        }
    }
}

impl SegmentSpec {
    /// A straight piece to `end` from `start` (from the previous segment's end if `None`) in
    /// `elements` equal elements, of the structure's section, its thickness direction the
    /// default.
    pub fn straight(start: Option<[f64; 3]>, end: [f64; 3], elements: usize) -> Self {
        Self {
            start,
            end: Some(end),
            centre: None,
            normal: None,
            angle_degrees: None,
            thickness_direction: None,
            elements,
            section: None,
            nodes: None,
        }
    }

    fn build(
        &self,
        index: usize,
        previous_end: Option<Vector3<f64>>,
        section: Section,
    ) -> Result<(Mesh, f64), SceneError> {
        let field = |name: &str| format!("segment[{index}].{name}");
        if !(1..=MAX_ELEMENTS).contains(&self.elements) {
            return Err(invalid(
                field("elements"),
                self.elements,
                "at least 1 element and at most 100000",
            ));
        }
        let start = match (self.start, previous_end) {
            (Some(s), None) => vector(&field("start"), s)?,
            (None, None) => Vector3::zeros(),
            (None, Some(p)) => p,
            (Some(s), Some(p)) => {
                let s = vector(&field("start"), s)?;
                if (s - p).norm() > 1e-9 * (1.0 + p.norm()) {
                    return Err(invalid(
                        field("start"),
                        point(&s),
                        &format!(
                            "the end of the previous segment, {} (or leave it out)",
                            point(&p)
                        ),
                    ));
                }
                p
            }
        };
        match (self.end, self.centre, self.normal, self.angle_degrees) {
            (Some(end), None, None, None) => {
                let end = vector(&field("end"), end)?;
                let axis = end - start;
                if axis.norm() < MIN_SEGMENT {
                    return Err(invalid(
                        field("end"),
                        point(&end),
                        &format!(
                            "a point at least {MIN_SEGMENT:e} m from the start (the segment's length is {:e} m)",
                            axis.norm()
                        ),
                    ));
                }
                let hint = match self.thickness_direction {
                    Some(d) => direction(&field("thickness_direction"), d)?,
                    None if axis.normalize().z.abs() > 0.99 => Vector3::x(),
                    None => Vector3::z(),
                };
                if hint.normalize().cross(&axis.normalize()).norm() < 1e-6 {
                    return Err(invalid(
                        field("thickness_direction"),
                        point(&hint),
                        "a direction not along the segment",
                    ));
                }
                let mesh = match &self.nodes {
                    Some(fractions) if fractions.len() != self.elements + 1 => {
                        return Err(SceneError::Inconsistent(format!(
                            "segment[{index}]: {} node places for {} elements",
                            fractions.len(),
                            self.elements
                        )))
                    }
                    Some(fractions) => {
                        Mesh::straight_through(start, end, fractions, section, hint)?
                    }
                    None => Mesh::straight(start, end, self.elements, section, hint)?,
                };
                Ok((mesh, axis.norm()))
            }
            (None, Some(centre), Some(normal), Some(angle)) => {
                let centre = vector(&field("centre"), centre)?;
                let normal = direction(&field("normal"), normal)?.normalize();
                if !(angle.is_finite() && angle != 0.0 && angle.abs() <= 360.0) {
                    return Err(invalid(
                        field("angle_degrees"),
                        angle,
                        "a non-zero angle within +-360 degrees",
                    ));
                }
                if self.thickness_direction.is_some() {
                    return Err(SceneError::Inconsistent(format!(
                        "{}: an arc's thickness direction is its normal",
                        field("thickness_direction")
                    )));
                }
                if self.nodes.is_some() {
                    return Err(SceneError::Inconsistent(format!(
                        "segment[{index}]: an arc's nodes are equally spaced"
                    )));
                }
                let radial = start - centre;
                let radius = radial.norm();
                if radius == 0.0 || normal.dot(&radial).abs() > 1e-9 * radius {
                    return Err(invalid(
                        field("centre"),
                        point(&centre),
                        "a point away from the start, in the plane through the start normal to `normal`",
                    ));
                }
                let length = radius * angle.to_radians().abs();
                if length < MIN_SEGMENT {
                    return Err(invalid(
                        field("centre"),
                        point(&centre),
                        &format!(
                            "a centre that makes the arc at least {MIN_SEGMENT:e} m long (radius {radius:e} m times {angle} degrees is {length:e} m)"
                        ),
                    ));
                }
                let mesh = Mesh::arc(
                    centre,
                    radius,
                    radial,
                    normal,
                    angle.to_radians(),
                    self.elements,
                    section,
                )?;
                Ok((mesh, length))
            }
            (end, centre, normal, angle) => Err(SceneError::Inconsistent(format!(
                "segment[{index}]: give `end` (straight) or `centre`, `normal` and `angle_degrees` \
                 (arc){}",
                if end.is_some() && (centre.is_some() || normal.is_some() || angle.is_some()) {
                    ", not both"
                } else {
                    ""
                }
            ))),
        }
    }
}

/// Arc length of every node along the true (curved) reference axis: what a user measures.
/// The mesh's own arc length sums the element chords, which falls short on an arc.
struct Stations(Vec<f64>);

/// The node at arc length `s` (m) of nodes at arc lengths `stations` (increasing, from 0), which
/// must be a node's: else `InvalidField` naming `field` and the nearest node.
///
/// # Errors
/// As said.
pub fn node_at(stations: &[f64], field: String, s: f64) -> Result<usize, SceneError> {
    let total = stations.last().copied().unwrap_or(0.0);
    let mut node = 0;
    for (i, si) in stations.iter().enumerate() {
        if (si - s).abs() < (stations[node] - s).abs() {
            node = i;
        }
    }
    if !s.is_finite() {
        return Err(invalid(field, s, &format!("the arc length of a node, from 0 to {total} m")));
    }
    if (stations[node] - s).abs() > 1e-9 * total.max(1.0) {
        return Err(invalid(
            field,
            s,
            &format!(
                "the arc length of a node, from 0 to {total} m (nearest node at {} m)",
                stations[node]
            ),
        ));
    }
    Ok(node)
}

/// `e` with its `section.` keys named under `prefix` (`segment[1].section.width`).
fn renamed(e: SceneError, prefix: &str) -> SceneError {
    match e {
        SceneError::InvalidField { field, value, allowed } => {
            SceneError::InvalidField { field: format!("{prefix}.{field}"), value, allowed }
        }
        SceneError::Inconsistent(message) if message.starts_with("section") => {
            SceneError::Inconsistent(format!("{prefix}.{message}"))
        }
        other => other,
    }
}

/// The beam of a `section`, a chain of `segments` and its `supports`: what a beam scene and an
/// impact scene's `[structure]` share (one parser, one validation), as the model and each
/// node's arc length from the start of the first segment (m). Errors name the keys as a beam
/// scene writes them (`segment[1].end`, `section.width`, `support[0].at`).
///
/// # Errors
/// `InvalidField` or `Inconsistent` naming the key at fault.
pub fn structure(
    section: &SectionSpec,
    segments: &[SegmentSpec],
    supports: &[SupportSpec],
) -> Result<(BeamModel, Vec<f64>), SceneError> {
    let section = section.build()?;
    if segments.is_empty() {
        return Err(SceneError::Inconsistent("the beam needs at least one [[segment]]".into()));
    }
    let mut mesh: Option<Mesh> = None;
    let mut stations = vec![0.0];
    // The previous segment's section and length, for the fold check.
    let mut previous: Option<(Section, f64)> = None;
    for (i, seg) in segments.iter().enumerate() {
        let previous_end = mesh.as_ref().and_then(|m| m.positions.last().copied());
        let own = match &seg.section {
            Some(spec) => spec.build().map_err(|e| renamed(e, &format!("segment[{i}]")))?,
            None => section,
        };
        let (piece, length) = seg.build(i, previous_end, own)?;
        if let (Some(m), Some((before, before_length))) = (&mesh, previous) {
            not_folded(i, seg, (m, before, before_length), (&piece, own, length))?;
        }
        previous = Some((own, length));
        let s0 = stations.last().copied().unwrap_or(0.0);
        // Nodes are equally spaced along each piece (in length or in angle), or where given.
        match &seg.nodes {
            Some(fractions) => stations.extend(fractions[1..].iter().map(|f| s0 + length * f)),
            None => stations
                .extend((1..=seg.elements).map(|k| s0 + length * k as f64 / seg.elements as f64)),
        }
        mesh = Some(match mesh {
            None => piece,
            Some(m) => m.join(piece)?,
        });
    }
    let mesh = mesh.ok_or_else(|| SceneError::Inconsistent("no segment".into()))?;
    let at = Stations(stations);
    let mut nodes: Vec<usize> = Vec::new();
    for (i, s) in supports.iter().enumerate() {
        let node = at.node(format!("support[{i}].at"), s.at)?;
        if let Some(j) = nodes.iter().position(|n| *n == node) {
            return Err(invalid(
                format!("support[{i}].at"),
                s.at,
                &format!(
                    "a node without a support: support[{j}] holds the same node; give one support per node (clamped holds what pinned holds and more)"
                ),
            ));
        }
        nodes.push(node);
    }
    let mut model = BeamModel::new(mesh)?;
    for (node, s) in nodes.into_iter().zip(supports) {
        model = model.support(node, s.kind)?;
    }
    Ok((model, at.0))
}

/// Refuses segment `i` where it folds back onto the one before so sharply that the two
/// members would lie inside each other beyond the shorter one's length: members of sections
/// of half depth c meeting at an angle phi overlap over c / tan(phi / 2) from the joint (a
/// segment straight back, phi = 0, over all of it). The depth is the section's deeper
/// side's (sqrt(3 EI_max / EA), the half side of a rectangle, 0.87 of a circle's radius),
/// whichever way the joint turns: a refusal errs toward folds a little wider. Sections as deep
/// as the shorter member are left to other checks.
fn not_folded(
    i: usize,
    seg: &SegmentSpec,
    (before, before_section, before_length): (&Mesh, Section, f64),
    (after, after_section, after_length): (&Mesh, Section, f64),
) -> Result<(), SceneError> {
    let (Some(end), Some(start)) = (before.frames.last(), after.frames.first()) else {
        return Ok(());
    };
    let back = -(end * Vector3::x());
    let angle = back.angle(&(start * Vector3::x()));
    let half_depth = |s: Section| (3.0 * s.ei2.max(s.ei3) / s.ea).sqrt();
    let depth = half_depth(before_section).max(half_depth(after_section));
    let overlap = depth / (0.5 * angle).tan();
    let shorter = before_length.min(after_length);
    // Sections as deep as the shorter member overlap at any angle: not a fold but members
    // that are no beams (most likely a section in mm, which the impact plan's unit checks
    // name).
    if overlap < shorter || depth >= shorter {
        return Ok(());
    }
    let least = 2.0 * (depth / shorter).atan().to_degrees();
    let (key, value) = match (seg.end, seg.centre) {
        (Some(end), _) => ("end", format!("{end:?}")),
        (None, centre) => ("centre", centre.map_or_else(String::new, |c| format!("{c:?}"))),
    };
    let how = if overlap.is_finite() {
        format!(
            "they meet at {:.3} degrees, so sections {} m deep on each side of the axis overlap \
             over {} m from the joint, beyond the shorter one's length {} m",
            angle.to_degrees(),
            show(round4(depth)),
            show(round4(overlap)),
            show(shorter),
        )
    } else {
        "it runs straight back along it".to_owned()
    };
    Err(invalid(
        format!("segment[{i}].{key}"),
        value,
        &format!(
            "a segment that does not fold back onto segment[{}]: {how}; here the angle between \
             them must exceed {least:.3} degrees",
            i - 1,
        ),
    ))
}

impl Stations {
    fn total(&self) -> f64 {
        self.0.last().copied().unwrap_or(0.0)
    }

    /// The node at arc length `s`, which must be a node's.
    fn node(&self, field: String, s: f64) -> Result<usize, SceneError> {
        node_at(&self.0, field, s)
    }

    /// The mesh's chord arc length at the true arc length `s`, interpolated within its element.
    fn to_mesh(&self, mesh: &Mesh, field: String, s: f64) -> Result<f64, SceneError> {
        let total = self.total();
        if !(s.is_finite() && (0.0..=total * (1.0 + 1e-12)).contains(&s)) {
            return Err(invalid(field, s, &format!("an arc length from 0 to {total} m")));
        }
        let i = self.0.windows(2).position(|w| s <= w[1]).unwrap_or(self.0.len().saturating_sub(2));
        let xi = ((s - self.0[i]) / (self.0[i + 1] - self.0[i])).clamp(0.0, 1.0);
        Ok(mesh.arc_length[i] + xi * (mesh.arc_length[i + 1] - mesh.arc_length[i]))
    }
}

fn rotation_vector(q: &UnitQuaternion<f64>, reference: &UnitQuaternion<f64>) -> [f64; 3] {
    (q * reference.inverse()).scaled_axis().into()
}

impl BeamScene {
    /// The natural modes of the scene's beam, linearised about its undeformed configuration
    /// without its loads, with `omega <= omega_max` (rad/s), ascending
    /// ([`crate::modes_below`]: banded shift-invert Lanczos, the count by Sylvester's inertia).
    ///
    /// # Errors
    /// `InvalidField` naming `omega_max` for a cutoff that is not finite and positive; the
    /// scene's own errors; [`BeamError::Eigen`] from the solver.
    pub fn modes_below(&self, omega_max: f64) -> Result<Vec<crate::Mode>, SceneError> {
        if !(omega_max.is_finite() && omega_max > 0.0) {
            return Err(SceneError::InvalidField {
                field: "omega_max".into(),
                value: show(omega_max),
                allowed: "must be a finite frequency greater than 0 (rad/s)".into(),
            });
        }
        let (model, _) = self.build()?;
        Ok(crate::modes_below(&model, omega_max)?)
    }

    /// The JSON Schema of a beam scene file (draft 2020-12), from the types the parser reads
    /// (`cargo xtask schema` writes it to docs/beam-scene.schema.json).
    pub fn schema() -> schemars::Schema {
        toml_schema::<BeamScene>("impact-beam beam scene")
    }

    /// Parses a beam scene from TOML text.
    ///
    /// # Errors
    /// `Parse` with the key and line for invalid TOML, unknown keys, missing fields and wrong
    /// types.
    pub fn from_toml(text: &str) -> Result<Self, SceneError> {
        toml::from_str(text).map_err(|e| SceneError::Parse(toml_message(&e)))
    }

    /// Builds the beam model: mesh, supports, loads.
    ///
    /// # Errors
    /// `InvalidField` or `Inconsistent` naming the field at fault.
    pub fn model(&self) -> Result<BeamModel, SceneError> {
        Ok(self.build()?.0)
    }

    fn build(&self) -> Result<(BeamModel, Stations), SceneError> {
        let (model, stations) = structure(&self.section, &self.segments, &self.supports)?;
        let mesh = model.mesh().clone();
        let stations = Stations(stations);
        let mut loads = Vec::new();
        for (i, l) in self.loads.iter().enumerate() {
            let field = |name: &str| format!("load[{i}].{name}");
            let at = stations.to_mesh(&mesh, field("at"), l.at)?;
            let profile = match &l.profile {
                None => Profile::Constant,
                Some(_) if self.analysis == AnalysisName::Static => {
                    return Err(SceneError::Inconsistent(format!(
                        "{}: a static analysis applies its loads by a load factor from 0 to 1, not in time; remove the profile, or use analysis = \"dynamic\"",
                        field("profile")
                    )));
                }
                Some(points) => {
                    if points.is_empty()
                        || points.iter().any(|p| !(p[0].is_finite() && p[1].is_finite()))
                        || points.windows(2).any(|w| w[1][0] < w[0][0])
                    {
                        return Err(invalid(
                            field("profile"),
                            format!("{points:?}"),
                            "a non-empty list of finite [time (s), factor] pairs, times not decreasing",
                        ));
                    }
                    Profile::Table(points.iter().map(|p| (p[0], p[1])).collect())
                }
            };
            let load = Load {
                node: 0,
                force: vector(&field("force"), l.force)?,
                moment: vector(&field("moment"), l.moment)?,
                follower: l.follower,
                profile,
            };
            loads.push((at, load));
        }
        let mut model = model;
        for (at, load) in loads {
            model = model.load_at(at, load)?;
        }
        Ok((model, stations))
    }

    /// A warning for each load profile that starts after t = 0 with a factor other than 0
    /// (held from t = 0, which a user may not expect).
    fn profile_warnings(&self) -> Vec<String> {
        self.loads
            .iter()
            .enumerate()
            .filter_map(|(i, l)| {
                let first = l.profile.as_ref()?.first()?;
                (first[0] > 0.0 && first[1] != 0.0).then(|| {
                    format!(
                        "load[{i}].profile starts at t = {:.4e} s with the factor {}: that factor is held from t = 0 (give a first point [0.0, 0.0] for a load that comes later)",
                        first[0], first[1]
                    )
                })
            })
            .collect()
    }

    /// Runs the scene. `progress` is called with the fraction done (0 to 1) after every load
    /// or time step.
    ///
    /// # Errors
    /// Any validation error of [`BeamScene::model`]; `StaticFailed` with the load factor reached
    /// when the static solver fails, `DynamicFailed` with the time reached when the integrator
    /// fails.
    pub fn run(&self, mut progress: impl FnMut(f64)) -> Result<BeamRun, SceneError> {
        let (model, stations) = self.build()?;
        let mesh = model.mesh().clone();
        let track = match self.output.track {
            None => mesh.positions.len() - 1,
            Some(s) => stations.node("output.track".into(), s)?,
        };
        let reference = model.reference_state();
        let sample = |x: f64, q: &BeamState, kinetic: f64| TrackSample {
            time_or_load: x,
            position: q.positions[track].into(),
            rotation: rotation_vector(&q.rotations[track], &reference.rotations[track]),
            strain_energy: model.strain_energy(q),
            kinetic_energy: kinetic,
        };
        // The largest axial and shear strains on the path, and the load factor or time of each.
        let largest = std::cell::Cell::new([(0.0, 0.0); 2]);
        let sample = |x: f64, q: &BeamState, kinetic: f64| {
            let (axial, shear) = model.largest_strains(q);
            let mut l = largest.get();
            for (k, strain) in [axial, shear].into_iter().enumerate() {
                if strain > l[k].0 {
                    l[k] = (strain, x);
                }
            }
            largest.set(l);
            sample(x, q, kinetic)
        };
        let clock = std::time::Instant::now();
        let mut history = vec![sample(0.0, &reference, 0.0)];
        let mut unstable = None;
        let (last, newton_iterations, cuts) = match self.analysis {
            AnalysisName::Static => {
                if self.dynamic.is_some() {
                    return Err(SceneError::Inconsistent(
                        "analysis = \"static\" takes a [static] table, not [dynamic]".into(),
                    ));
                }
                if self.supports.is_empty() {
                    return Err(SceneError::Inconsistent(
                        "a static analysis needs at least one [[support]] (a free beam has no \
                         equilibrium under load)"
                            .into(),
                    ));
                }
                let load_steps = self.statics.and_then(|s| s.load_steps).unwrap_or(10);
                if !(1..=MAX_LOAD_STEPS).contains(&load_steps) {
                    return Err(invalid(
                        "static.load_steps".into(),
                        load_steps,
                        "at least 1 and at most 1000000",
                    ));
                }
                let options = StaticOptions { load_steps, ..StaticOptions::default() };
                let solution = solve_static(&model, options).map_err(|e| match e {
                    BeamError::NotConverged { load_factor, .. } => {
                        SceneError::StaticFailed { load_factor, source: e }
                    }
                    // The linear solver reports the load factor as a time; what it means here is
                    // that nothing holds the beam (its message would name a time).
                    BeamError::Integrator(hht::HhtError::Singular { t, .. }) => {
                        SceneError::Mechanism { load_factor: t }
                    }
                    other => other.into(),
                })?;
                for (lambda, q) in &solution.path {
                    history.push(sample(*lambda, q, 0.0));
                }
                unstable = solution.unstable_from;
                progress(1.0);
                (solution.state, solution.iterations.iter().sum(), solution.cuts)
            }
            AnalysisName::Dynamic => {
                let Some(spec) = self.dynamic else {
                    return Err(SceneError::Inconsistent(
                        "analysis = \"dynamic\" needs a [dynamic] table with duration and time_step"
                            .into(),
                    ));
                };
                if self.statics.is_some() {
                    return Err(SceneError::Inconsistent(
                        "analysis = \"dynamic\" takes a [dynamic] table, not [static]".into(),
                    ));
                }
                positive("dynamic.duration", spec.duration, "s")?;
                positive("dynamic.time_step", spec.time_step, "s")?;
                if spec.time_step > spec.duration {
                    return Err(invalid(
                        "dynamic.time_step".into(),
                        show(spec.time_step),
                        &format!(
                            "at most dynamic.duration ({} s): one step would be cut to the duration",
                            show(spec.duration)
                        ),
                    ));
                }
                let steps = (spec.duration / spec.time_step).ceil();
                if steps > 1e8 {
                    return Err(invalid(
                        "dynamic.time_step".into(),
                        spec.time_step,
                        "at most 1e8 steps in the duration",
                    ));
                }
                let alpha = spec.alpha.unwrap_or(0.0);
                let scheme = Scheme::hht(alpha).map_err(|_| {
                    invalid("dynamic.alpha".into(), alpha, "a number in [-1/3, 0] (HHT-alpha)")
                })?;
                let mut integrator = Integrator::new(scheme, NewtonOptions::default());
                let fail = |source: hht::HhtError, t: f64| SceneError::DynamicFailed { t, source };
                let mut state = integrator
                    .initial_state(&model, 0.0, reference.clone(), Col::zeros(model.ndof()))
                    .map_err(|e| fail(e, 0.0))?;
                let steps = steps as usize;
                let (mut iterations, mut cuts) = (0, 0);
                for k in 0..steps {
                    let h = (spec.duration - state.t).min(spec.time_step);
                    let report =
                        integrator.step(&model, &mut state, h).map_err(|e| fail(e, state.t))?;
                    iterations += report.iterations;
                    cuts += report.substeps.saturating_sub(1);
                    history.push(sample(state.t, &state.q, model.kinetic_energy(state.v.as_ref())));
                    progress((k + 1) as f64 / steps as f64);
                }
                (state.q, iterations, cuts)
            }
        };
        let shape = (0..mesh.positions.len())
            .map(|i| ShapeNode {
                arc_length: stations.0[i],
                position: last.positions[i].into(),
                rotation: rotation_vector(&last.rotations[i], &reference.rotations[i]),
            })
            .collect();
        let at = match self.analysis {
            AnalysisName::Static => "at load factor",
            AnalysisName::Dynamic => "at t =",
        };
        let mut warnings = self.profile_warnings();
        warnings.extend(
            ["axial", "shear"]
                .iter()
                .zip(largest.get())
                .filter(|(_, (strain, _))| *strain > SMALL_STRAIN)
                .map(|(kind, (strain, x))| {
                    format!(
                        "the largest {kind} strain is {strain:.3e} ({at} {x:.4e}), beyond the {SMALL_STRAIN} the linear elastic section law is meant for: the result extrapolates the material"
                    )
                }),
        );
        if let Some((lambda, k)) = unstable {
            warnings.push(format!(
                "the equilibrium is unstable from load factor {lambda:.4e} on: its tangent stiffness has {k} negative eigenvalue(s) (Sylvester's inertia), so the beam is past a buckling load and the shape found is one it would not keep (the load path from the unloaded beam stays on the branch it started on); the stable shape lies on another branch, which load control from the unloaded beam does not follow (with a small load across as an imperfection it may still stop on an unstable branch, as this warning would then say again)"
            ));
        }
        Ok(BeamRun {
            warnings,
            name: self.name.clone(),
            tracked_arc_length: stations.0[track],
            analysis: self.analysis,
            history,
            shape,
            unknowns: model.ndof(),
            newton_iterations,
            cuts,
            wall_time: clock.elapsed().as_secs_f64(),
        })
    }
}

impl BeamRun {
    /// Writes the tracked node's history as CSV: `time_s` (dynamics) or `load_factor_-`
    /// (statics), `x_m`, `y_m`, `z_m`, rotation vector `rx_rad`, `ry_rad`, `rz_rad`,
    /// `strain_energy_j`, `kinetic_energy_j`.
    ///
    /// # Errors
    /// I/O errors of `out`.
    pub fn write_history_csv(&self, mut out: impl std::io::Write) -> std::io::Result<()> {
        let first = match self.analysis {
            AnalysisName::Static => "load_factor_-",
            AnalysisName::Dynamic => "time_s",
        };
        writeln!(out, "{first},x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,strain_energy_j,kinetic_energy_j")?;
        for s in &self.history {
            let [x, y, z] = s.position;
            let [rx, ry, rz] = s.rotation;
            writeln!(
                out,
                "{:e},{x:e},{y:e},{z:e},{rx:e},{ry:e},{rz:e},{:e},{:e}",
                s.time_or_load, s.strain_energy, s.kinetic_energy
            )?;
        }
        Ok(())
    }

    /// Writes the final configuration as CSV: `arc_length_m`, `x_m`, `y_m`, `z_m`, `rx_rad`,
    /// `ry_rad`, `rz_rad`, one row per node.
    ///
    /// # Errors
    /// I/O errors of `out`.
    pub fn write_shape_csv(&self, mut out: impl std::io::Write) -> std::io::Result<()> {
        writeln!(out, "arc_length_m,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad")?;
        for n in &self.shape {
            let [x, y, z] = n.position;
            let [rx, ry, rz] = n.rotation;
            writeln!(out, "{:e},{x:e},{y:e},{z:e},{rx:e},{ry:e},{rz:e}", n.arc_length)?;
        }
        Ok(())
    }
}
