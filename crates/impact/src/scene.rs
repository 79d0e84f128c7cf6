//! The scene file: what a user writes (TOML, SI units).

use crate::error::ImpactError;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use simo_beam::scene::toml_message;

/// A ball striking a beam (or a massive half-space). Every unknown key is an error.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Name used in reports and file names.
    pub name: String,
    /// The struck beam; exactly one of `beam`, `half_space` and `structure`.
    pub beam: Option<BeamSpec>,
    /// A massive elastic block (no beam); exactly one of `beam`, `half_space` and `structure`.
    pub half_space: Option<HalfSpaceSpec>,
    /// A structure of beams (segments, straight or arcs, meeting at rigid joints; supports at
    /// arc lengths): the fe method's 3D beam, or (`solver.method = "modal"`) Goldsmith's method
    /// on that beam's own modes; exactly one of `beam`, `half_space` and `structure`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub structure: Option<StructureSpec>,
    /// The striking ball.
    pub ball: BallSpec,
    /// Where and how fast it strikes.
    pub impact: ImpactSpec,
    /// The contact law.
    #[serde(default)]
    pub contact: ContactSpec,
    /// Method and resolution.
    #[serde(default)]
    pub solver: SolverSpec,
}

/// End conditions of a beam, as written in a scene file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", try_from = "toml::Value")]
pub enum SupportName {
    /// Clamped at x = 0, free at x = L.
    ClampedFree,
    /// Pinned at both ends.
    PinnedPinned,
    /// Clamped at both ends.
    ClampedClamped,
    /// Clamped at x = 0, pinned at x = L.
    ClampedPinned,
    /// Free at both ends.
    FreeFree,
}

/// One of `names` by its spelling in a scene file; anything else is an error that lists them.
fn named<T: Copy>(value: toml::Value, names: &[(&str, T, &str)]) -> Result<T, String> {
    let allowed = names.iter().map(|(n, ..)| format!("\"{n}\"")).collect::<Vec<_>>().join(", ");
    match &value {
        toml::Value::String(s) => names
            .iter()
            .find(|(n, ..)| n == s)
            .map(|(_, v, _)| *v)
            .ok_or_else(|| format!("\"{s}\" is not one of {allowed}")),
        other => Err(format!("{other} is not one of {allowed}")),
    }
}

/// The JSON Schema of a value [`named`] reads: a string, one of the names, each with its
/// meaning in the description (what an editor shows on hover).
fn named_schema<T>(what: &str, names: &[(&str, T, &str)]) -> schemars::Schema {
    let meanings: Vec<String> = names.iter().map(|(n, _, m)| format!("`{n}`: {m}")).collect();
    let values: Vec<&str> = names.iter().map(|(n, ..)| *n).collect();
    schemars::json_schema!({
        "type": "string",
        "description": format!("{what} {}", meanings.join("; ")),
        "enum": values,
    })
}

/// A scene's choice among names (`kind = "name"`): its spellings and meanings in one table,
/// read by `TryFrom<toml::Value>` (the error lists them) and described by its JSON Schema.
macro_rules! named_choice {
    ($type:ident, $what:literal, [$(($name:literal, $value:ident, $meaning:literal)),+ $(,)?]) => {
        impl $type {
            /// The spellings a scene file may use, with the value and its meaning.
            pub const NAMES: &'static [(&'static str, $type, &'static str)] =
                &[$(($name, $type::$value, $meaning)),+];
        }

        impl TryFrom<toml::Value> for $type {
            type Error = String;
            fn try_from(value: toml::Value) -> Result<Self, String> {
                named(value, Self::NAMES)
            }
        }

        impl JsonSchema for $type {
            fn schema_name() -> std::borrow::Cow<'static, str> {
                stringify!($type).into()
            }
            fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
                named_schema($what, Self::NAMES)
            }
        }
    };
}

named_choice!(
    SupportName,
    "End conditions.",
    [
        ("clamped-free", ClampedFree, "clamped at x = 0, free at x = L"),
        ("pinned-pinned", PinnedPinned, "pinned at both ends"),
        ("clamped-clamped", ClampedClamped, "clamped at both ends"),
        ("clamped-pinned", ClampedPinned, "clamped at x = 0, pinned at x = L"),
        ("free-free", FreeFree, "free at both ends"),
    ]
);

named_choice!(
    LawName,
    "The contact law.",
    [
        ("hertz", Hertz, "elastic Hertz"),
        (
            "hunt-crossley",
            HuntCrossley,
            "Hertz with Hunt-Crossley damping (`damping` or `restitution`)"
        ),
        (
            "thornton",
            Thornton,
            "Thornton elastic-perfectly-plastic (a yield stress or `limiting_pressure`)"
        ),
    ]
);

named_choice!(
    MethodName,
    "The solution method.",
    [
        ("auto", Auto, "the plan chooses, and says why"),
        ("modal", Modal, "Goldsmith's modal method"),
        ("fe", Fe, "the geometrically exact finite-element beam (Simo) with HHT-alpha"),
    ]
);

named_choice!(
    TheoryName,
    "The modal method's beam theory.",
    [
        (
            "euler-bernoulli",
            EulerBernoulli,
            "plane sections stay normal to the axis; no rotary inertia"
        ),
        ("timoshenko", Timoshenko, "shear deformation and rotary inertia"),
    ]
);

named_choice!(
    FeModelName,
    "The fe method's beam.",
    [
        (
            "planar",
            Planar,
            "the rod in the x-z plane (3 unknowns a node): what a centred strike moves"
        ),
        (
            "3d",
            ThreeD,
            "Simo's 3D rod (6 unknowns a node): bending both ways, extension, shear and twist"
        ),
    ]
);

named_choice!(
    ModalBasisName,
    "The modal method's modes.",
    [
        (
            "analytic",
            Analytic,
            "the uniform beam's analytic modes (Euler-Bernoulli or Timoshenko, with Saint-Venant torsion off the centreline): a `[beam]` without masses or springs"
        ),
        (
            "fe",
            Fe,
            "the structure's own modes, from its 3D finite-element beam linearised at rest (masses, springs, supports, steps, corners)"
        ),
    ]
);

impl SupportName {
    /// How the beam's two ends (x = 0, x = L) are held: the one table of what each name means
    /// (the modal method's analytic supports follow from it too).
    pub fn ends(self) -> [simo_beam::Support; 2] {
        use simo_beam::Support::{Clamped, Free, Pinned};
        match self {
            SupportName::ClampedFree => [Clamped, Free],
            SupportName::PinnedPinned => [Pinned, Pinned],
            SupportName::ClampedClamped => [Clamped, Clamped],
            SupportName::ClampedPinned => [Clamped, Pinned],
            SupportName::FreeFree => [Free, Free],
        }
    }
}

impl From<SupportName> for modal::Support {
    fn from(s: SupportName) -> Self {
        match s {
            SupportName::ClampedFree => modal::Support::ClampedFree,
            SupportName::PinnedPinned => modal::Support::PinnedPinned,
            SupportName::ClampedClamped => modal::Support::ClampedClamped,
            SupportName::ClampedPinned => modal::Support::ClampedPinned,
            SupportName::FreeFree => modal::Support::FreeFree,
        }
    }
}

/// A uniform beam of rectangular section, struck on its `thickness` face.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BeamSpec {
    /// Length L (m).
    #[schemars(range(min = 1e-9, max = 1e4), extend("x-unit" = "m"))]
    pub length: f64,
    /// Section width b (m).
    #[schemars(range(min = 1e-9, max = 1e4), extend("x-unit" = "m"))]
    pub width: f64,
    /// Section thickness h (m), in the direction of impact.
    #[schemars(range(min = 1e-9, max = 1e4), extend("x-unit" = "m"))]
    pub thickness: f64,
    /// End conditions.
    pub support: SupportName,
    /// Young's modulus E (Pa).
    #[schemars(range(min = 1e3, max = 1e13), extend("x-unit" = "Pa"))]
    pub youngs_modulus: f64,
    /// Poisson's ratio (-).
    #[schemars(extend("exclusiveMinimum" = -1, "exclusiveMaximum" = 0.5))]
    pub poisson_ratio: f64,
    /// Density (kg/m^3).
    #[schemars(range(min = 1e-3, max = 1e6), extend("x-unit" = "kg/m^3"))]
    pub density: f64,
    /// Yield stress (Pa); needed by plastic contact laws.
    #[schemars(range(min = 1e3, max = 1e13), extend("x-unit" = "Pa"))]
    pub yield_stress: Option<f64>,
    /// Modal damping ratio of every elastic mode (-), default 0.
    #[schemars(range(min = 0), extend("exclusiveMaximum" = 1, "default" = 0))]
    pub modal_damping: Option<f64>,
    /// Point masses on the beam (`[[beam.mass]]`): sensors, tip masses.
    #[serde(default, rename = "mass", skip_serializing_if = "Vec::is_empty")]
    pub masses: Vec<MassSpec>,
    /// Elastic supports (`[[beam.spring]]`).
    #[serde(default, rename = "spring", skip_serializing_if = "Vec::is_empty")]
    pub springs: Vec<SpringSpec>,
}

/// A structure of beams (`[structure]`), described as a beam scene describes its beam (one
/// parser, `simo_beam::scene::structure`): a rectangular `section` of a material, a chain of
/// `segment`s, `support`s at arc lengths.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StructureSpec {
    /// The section (`youngs_modulus`, `poisson_ratio`, `density`, `width`, `thickness`).
    pub section: simo_beam::scene::SectionSpec,
    /// The members, in order along the chain.
    #[serde(rename = "segment")]
    pub segments: Vec<simo_beam::scene::SegmentSpec>,
    /// Supports (`at` = arc length (m), `kind` = clamped | pinned).
    #[serde(rename = "support", default)]
    pub supports: Vec<simo_beam::scene::SupportSpec>,
    /// Yield stress (Pa); needed by plastic contact laws.
    #[schemars(range(min = 1e3, max = 1e13), extend("x-unit" = "Pa"))]
    pub yield_stress: Option<f64>,
    /// Point masses at nodes (`at` = arc length, m), with their rotary inertia about the
    /// member's axis.
    #[serde(default, rename = "mass", skip_serializing_if = "Vec::is_empty")]
    pub masses: Vec<MassSpec>,
    /// Springs at nodes (`at` = arc length, m): translational, and rotational if given.
    #[serde(default, rename = "spring", skip_serializing_if = "Vec::is_empty")]
    pub springs: Vec<StructureSpringSpec>,
    /// Written by the plan for a `[beam]` that carries masses or springs (never read from a
    /// file): its messages then name what a `[beam]` can set.
    #[serde(skip)]
    #[schemars(skip)]
    pub(crate) lowered: bool,
}

impl StructureSpec {
    /// A structure of `segments` of `section`, held by `supports`, without masses, springs or
    /// a yield stress (set the public fields for them): how a program builds a `[structure]`
    /// without a file (a private field had made the struct unbuildable in code, a review's).
    pub fn new(
        section: simo_beam::scene::SectionSpec,
        segments: Vec<simo_beam::scene::SegmentSpec>,
        supports: Vec<simo_beam::scene::SupportSpec>,
    ) -> Self {
        Self {
            section,
            segments,
            supports,
            yield_stress: None,
            masses: Vec::new(),
            springs: Vec::new(),
            lowered: false,
        }
    }
}

/// An elastic support on a structure (`[[structure.spring]]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StructureSpringSpec {
    /// Where (m of arc length from the start of the first segment): a node.
    #[schemars(range(min = 0), extend("x-unit" = "m"))]
    pub at: f64,
    /// Stiffness along x, y and z (N/m) against the node's displacement.
    #[serde(deserialize_with = "simo_beam::scene::exactly")]
    #[schemars(extend("x-unit" = "N/m"))]
    pub stiffness: [f64; 3],
    /// Stiffness against the node's section rotation from its reference orientation, about
    /// the section's axes E1 (the member's axis: its twist), E2 (the width axis) and E3 (the
    /// thickness axis) (N m/rad), default none: a bolted joint, a partly fixed end.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "simo_beam::scene::exactly_some"
    )]
    #[schemars(extend("x-unit" = "N m/rad"))]
    pub rotational_stiffness: Option<[f64; 3]>,
}

/// A point mass (`[[beam.mass]]`, `[[structure.mass]]`): a sensor, a tip mass.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MassSpec {
    /// Where (m): from x = 0 on a `[beam]`, the arc length of a node on a `[structure]`.
    #[schemars(range(min = 0), extend("x-unit" = "m"))]
    pub at: f64,
    /// Mass (kg).
    #[schemars(range(min = 0), extend("x-unit" = "kg"))]
    pub mass: f64,
    /// Rotary inertia (kg m^2), default 0: a number, about the member's axis (it resists the
    /// twist only); or `[J1, J2, J3]` about the section's axes E1 (the member's axis), E2 (the
    /// width axis: the bending a strike on the thickness face turns the section by) and E3
    /// (the thickness axis); at a structure's corner node, the axes of the member that reaches
    /// it (the first of the two). A compact block's J2 lowers a cantilever's second bending
    /// frequency by several per cent (validation/REFERENCES.md 1.10).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("x-unit" = "kg m^2"), extend("default" = 0))]
    pub rotary_inertia: Option<RotaryInertia>,
}

/// A point mass's rotary inertia (`rotary_inertia` of `[[beam.mass]]`, `[[structure.mass]]`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
#[serde(untagged)]
pub enum RotaryInertia {
    /// About the member's axis only (kg m^2): a number.
    Axis(#[schemars(range(min = 0))] f64),
    /// About the section's axes E1, E2, E3 (kg m^2): three numbers.
    Axes(#[schemars(length(equal = 3))] [f64; 3]),
}

impl RotaryInertia {
    /// About E1, E2 and E3 (kg m^2).
    pub fn axes(self) -> [f64; 3] {
        match self {
            Self::Axis(j) => [j, 0.0, 0.0],
            Self::Axes(j) => j,
        }
    }
}

impl<'de> Deserialize<'de> for RotaryInertia {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Either;
        impl<'de> serde::de::Visitor<'de> for Either {
            type Value = RotaryInertia;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number (kg m^2, about the member's axis) or an array of three [about E1 (the axis), E2 (the width axis), E3 (the thickness axis)]")
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<RotaryInertia, E> {
                Ok(RotaryInertia::Axis(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<RotaryInertia, E> {
                Ok(RotaryInertia::Axis(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<RotaryInertia, E> {
                Ok(RotaryInertia::Axis(v as f64))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<RotaryInertia, A::Error> {
                let mut values = Vec::new();
                while let Some(v) = seq.next_element::<f64>()? {
                    values.push(v);
                }
                let n = values.len();
                <[f64; 3]>::try_from(values).map(RotaryInertia::Axes).map_err(|_| {
                    serde::de::Error::invalid_length(n, &"an array of three [J1, J2, J3]")
                })
            }
        }
        d.deserialize_any(Either)
    }
}

/// An elastic support on a beam (`[[beam.spring]]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SpringSpec {
    /// Where (m from x = 0).
    #[schemars(range(min = 0), extend("x-unit" = "m"))]
    pub at: f64,
    /// Stiffness along the impact direction (N/m).
    #[schemars(range(min = 0), extend("x-unit" = "N/m"))]
    pub stiffness: f64,
    /// Stiffness against the section's bending rotation (N m/rad), default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0), extend("x-unit" = "N m/rad"), extend("default" = 0))]
    pub rotational_stiffness: Option<f64>,
}

/// A massive elastic block: the ball's counterface does not move.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HalfSpaceSpec {
    /// Young's modulus E (Pa).
    #[schemars(range(min = 1e3, max = 1e13), extend("x-unit" = "Pa"))]
    pub youngs_modulus: f64,
    /// Poisson's ratio (-).
    #[schemars(extend("exclusiveMinimum" = -1, "exclusiveMaximum" = 0.5))]
    pub poisson_ratio: f64,
    /// Yield stress (Pa); needed by plastic contact laws.
    #[schemars(range(min = 1e3, max = 1e13), extend("x-unit" = "Pa"))]
    pub yield_stress: Option<f64>,
}

/// A solid elastic sphere.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BallSpec {
    /// Radius (m).
    #[schemars(range(min = 1e-9, max = 1e4), extend("x-unit" = "m"))]
    pub radius: f64,
    /// Mass (kg); default density x volume.
    #[schemars(range(min = 1e-12, max = 1e6), extend("x-unit" = "kg"))]
    pub mass: Option<f64>,
    /// Young's modulus E (Pa).
    #[schemars(range(min = 1e3, max = 1e13), extend("x-unit" = "Pa"))]
    pub youngs_modulus: f64,
    /// Poisson's ratio (-).
    #[schemars(extend("exclusiveMinimum" = -1, "exclusiveMaximum" = 0.5))]
    pub poisson_ratio: f64,
    /// Density (kg/m^3).
    #[schemars(range(min = 1e-3, max = 1e6), extend("x-unit" = "kg/m^3"))]
    pub density: f64,
    /// Yield stress (Pa), if the ball can yield.
    #[schemars(range(min = 1e3, max = 1e13), extend("x-unit" = "Pa"))]
    pub yield_stress: Option<f64>,
}

/// Where and how fast the ball strikes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ImpactSpec {
    /// Impact point (m) from x = 0 (the first support); required with a beam. At most the beam's
    /// length, and not on a supported end (the ball would meet a rigid face there: refused).
    #[schemars(range(min = 0), extend("x-unit" = "m"))]
    pub position: Option<f64>,
    /// Impact point on a `[structure]`: arc length along its chain of segments (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0), extend("x-unit" = "m"))]
    pub at: Option<f64>,
    /// The ball's velocity direction on a `[structure]` (any length): normal to a face of the
    /// struck section (a thickness face, normal E3, or a width face, normal E2; anything else
    /// is refused naming them: no friction is modelled).
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "simo_beam::scene::exactly_some"
    )]
    pub direction: Option<[f64; 3]>,
    /// The strike's distance from the beam's centreline across its width (m; default 0, a
    /// centred strike): the contact force twists the beam by offset x force. At most half
    /// the width (the face's edge).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("x-unit" = "m"), extend("default" = 0))]
    pub offset: Option<f64>,
    /// Drop height h (m): speed sqrt(2 g h). Exactly one of `drop_height` and `speed`.
    #[schemars(extend("exclusiveMinimum" = 0), extend("x-unit" = "m"))]
    pub drop_height: Option<f64>,
    /// Impact speed (m/s), toward the beam.
    #[schemars(range(min = 1e-6, max = 1e4), extend("x-unit" = "m/s"))]
    pub speed: Option<f64>,
    /// Whether gravity (9.81 m/s^2, toward the beam) acts on the ball during the run; on a
    /// `[structure]` (z up) only with a strike straight down, `impact.direction = [0, 0, -1]`.
    #[serde(default = "default_gravity")]
    pub gravity: bool,
}

fn default_gravity() -> bool {
    true
}

/// Contact laws a scene can ask for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", try_from = "toml::Value")]
pub enum LawName {
    /// Elastic Hertz.
    #[default]
    Hertz,
    /// Hertz with Hunt-Crossley damping (`damping` or `restitution`).
    HuntCrossley,
    /// Thornton elastic-perfectly-plastic (a yield stress or `limiting_pressure`).
    Thornton,
}

impl LawName {
    /// The name as a scene file writes it (its entry in [`LawName::NAMES`]).
    pub fn as_str(self) -> &'static str {
        Self::NAMES.iter().find(|(_, law, _)| *law == self).map_or("", |(name, ..)| name)
    }
}

impl std::fmt::Display for LawName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The contact law and its parameters.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// Which law.
    #[serde(default)]
    pub law: LawName,
    /// Hunt-Crossley damping factor chi (s/m).
    #[schemars(range(min = 0, max = 1e6), extend("x-unit" = "s/m"))]
    pub damping: Option<f64>,
    /// Hunt-Crossley: target restitution at the impact speed, instead of `damping`.
    #[schemars(range(max = 1), extend("exclusiveMinimum" = 0))]
    pub restitution: Option<f64>,
    /// Thornton: limiting contact pressure (Pa); default 1.6 x the softer yield stress.
    #[schemars(range(min = 1e3, max = 1e13), extend("x-unit" = "Pa"))]
    pub limiting_pressure: Option<f64>,
}

/// Solution methods.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", try_from = "toml::Value")]
pub enum MethodName {
    /// Let the plan choose.
    #[default]
    Auto,
    /// Goldsmith's modal method.
    Modal,
    /// The geometrically exact finite-element beam (Simo) with HHT-alpha.
    Fe,
}

/// The fe method's beam model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", try_from = "toml::Value")]
pub enum FeModelName {
    /// The rod in the x-z plane: what a centred strike moves.
    Planar,
    /// The 3D rod: bending both ways, extension, shear and twist.
    #[serde(rename = "3d")]
    ThreeD,
}

/// Where the modal method's modes come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", try_from = "toml::Value")]
pub enum ModalBasisName {
    /// The uniform beam's analytic modes.
    Analytic,
    /// The structure's own modes from its finite elements.
    Fe,
}

/// Beam theories of the modal method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", try_from = "toml::Value")]
pub enum TheoryName {
    /// Plane sections stay normal to the axis; no rotary inertia.
    EulerBernoulli,
    /// Shear deformation and rotary inertia.
    Timoshenko,
}

/// Method and resolution; every field has a default.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    /// Method.
    #[serde(default)]
    pub method: MethodName,
    /// Number of modes (modal method, on a uniform `[beam]`'s analytic modes); default all
    /// below omega t_c = 20 for the estimated contact duration t_c, or below 12 times the
    /// contact's local frequency where that is higher (a ball heavy against the beam; the plan
    /// says which). The finite-element modes of a `[structure]` or of a beam with masses or
    /// springs are all those below the pulse's cutoff: refused there (`tolerance` refines them).
    #[schemars(range(min = 1, max = 20_000))]
    pub modes: Option<usize>,
    /// Beam theory of the modal method's modes, "euler-bernoulli" or "timoshenko"; default
    /// chosen by the plan (Timoshenko unless shear and rotary inertia change nothing the
    /// contact excites). The fe beam always has shear and rotary inertia.
    pub beam_theory: Option<TheoryName>,
    /// Where the modal method's modes come from: `analytic` (a uniform `[beam]`) or `fe` (the
    /// 3D finite-element beam's own modes); default analytic on a `[beam]` without masses or
    /// springs, fe otherwise, and on a free-free `[beam]` struck off its centreline (a free
    /// body: its own modes carry the truncated modes' static share by inertia relief; unless
    /// `modes` or `beam_theory` is given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub modal_basis: Option<ModalBasisName>,
    /// Simulated time (s) from first touch; default 5 ms on a beam or a structure, four times
    /// the contact's own length on a rigid support on a half-space (Hertz's, or a damped
    /// Hunt-Crossley contact's creeping exit).
    #[schemars(range(min = 1e-12, max = 1e4), extend("x-unit" = "s"))]
    pub end_time: Option<f64>,
    /// Time steps per estimated contact duration (the largest contact step of the modal and
    /// half-space methods, which adapt it below that; the fe method's smallest).
    #[schemars(range(min = 10, max = 1_000_000))]
    pub samples_per_pulse: Option<usize>,
    /// Modal and half-space methods: allowed energy mismatch of the contact steps, as a
    /// fraction of the impact energy per estimated contact duration; default 1e-6.
    #[schemars(extend("exclusiveMinimum" = 0, "exclusiveMaximum" = 1, "default" = 1e-6))]
    pub energy_tolerance: Option<f64>,
    /// Modal and half-space methods: adapt the contact step to `energy_tolerance` (default
    /// true); false takes uniform steps of the estimated duration / samples_per_pulse.
    #[schemars(extend("default" = true))]
    pub adaptive_step: Option<bool>,
    /// Modal method: put the truncated modes' static compliance at the impact point (the
    /// beam's static flexibility minus the kept modes' share) in series with the contact, as
    /// the mode-acceleration method does: the modes above the cutoff answer the force
    /// quasi-statically. Default false on a `[beam]` struck on its centre line (true with
    /// `tolerance`, and where the kept modes leave out more than 1 % of the static flexibility
    /// at the impact point, as near a support: the plan says so), true off it
    /// (`impact.offset`: the torsion modes' static share falls only as 1/N) and on a
    /// `[structure]` (on a free one by inertia relief).
    #[schemars(extend("default" = false))]
    pub residual_flexibility: Option<bool>,
    /// Modal method: recover the bending stress by the plain modal series
    /// M = EI sum q_n phi_n'' instead of the mode-acceleration form (which adds the truncated
    /// modes' quasi-static share and converges far faster near the ball); for studies of the
    /// series itself. Default false.
    #[schemars(extend("default" = false))]
    pub plain_stress_series: Option<bool>,
    /// Interval of the recorded history in free flight (s).
    #[schemars(extend("exclusiveMinimum" = 0), extend("x-unit" = "s"))]
    pub output_interval: Option<f64>,
    /// Number of equal finite elements (fe method); default elements of `element_size` as far
    /// from the impact point as the pulse's waves reach within the window, growing beyond.
    #[schemars(range(min = 1, max = 100_000))]
    pub elements: Option<usize>,
    /// Element length (m) of the default mesh (fe method) as far from the impact point as the
    /// pulse's waves reach within the window (their group velocity at omega t_c = 20 times
    /// `end_time`), the elements growing by 1.15 each beyond; default 1/16 of the flexural
    /// wavelength at that frequency, the fastest the pulse excites.
    #[schemars(extend("exclusiveMinimum" = 0), extend("x-unit" = "m"))]
    pub element_size: Option<f64>,
    /// HHT alpha in [-1/3, 0] (fe method); default -0.05.
    #[schemars(range(min = -0.333_333_333_333_333_3, max = 0), extend("default" = -0.05))]
    pub alpha: Option<f64>,
    /// The fe method's beam: `planar` (x-z, 3 unknowns a node) or `3d` (Simo's rod, 6 a node:
    /// twist); default planar for a centred strike, 3d off the centreline.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fe_model: Option<FeModelName>,
    /// Largest time step (s) (fe method); default the contact step (every step of the same
    /// length: converged in time, validation/REFERENCES.md 1.7); a longer one lets the steps out
    /// of contact, and in a long contact, grow up to it; a shorter one sets every step (in
    /// contact too: as many per estimated contact duration as it takes).
    #[schemars(extend("exclusiveMinimum" = 0), extend("x-unit" = "s"))]
    pub time_step: Option<f64>,
    /// Relative error accepted on every significant contact (start, duration, peak force) and
    /// on the largest displacement, instead of a resolution: the fe method refines a uniform
    /// mesh (with a node at the impact point), the modal method doubles its modes, until two
    /// successive runs agree within it.
    #[schemars(extend("exclusiveMinimum" = 0, "exclusiveMaximum" = 1))]
    pub tolerance: Option<f64>,
}

impl Scene {
    /// The JSON Schema of a scene file (draft 2020-12), from the types the parser reads: every
    /// key with its documentation, unit (`x-unit`), default and bounds. Editors that read TOML
    /// with a schema (Taplo, the "Even Better TOML" extension) complete and check a scene that
    /// names it on its first line (`#:schema`); `cargo xtask schema` writes it to
    /// docs/scene.schema.json.
    pub fn schema() -> schemars::Schema {
        simo_beam::scene::toml_schema::<Scene>("impact-beam scene")
    }

    /// Parses a scene from TOML text.
    ///
    /// # Errors
    /// `Parse` with the key and line for invalid TOML, unknown keys, missing fields and wrong
    /// types.
    pub fn from_toml(text: &str) -> Result<Self, ImpactError> {
        toml::from_str(text).map_err(|e| ImpactError::Parse(toml_message(&e)))
    }

    /// Reads a scene from the table a scene file parses to (a front end's dictionary with
    /// the file's tables and keys), with the checks of [`Scene::from_toml`].
    ///
    /// # Errors
    /// `Parse` naming the key for unknown keys, missing fields and wrong types.
    pub fn from_table(table: toml::Table) -> Result<Self, ImpactError> {
        toml::Value::Table(table)
            .try_into()
            .map_err(|e: toml::de::Error| ImpactError::Parse(toml_message(&e)))
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn every_named_choice_reads_back_by_its_name_and_refuses_others_listing_them() {
        // The one table of each choice is what the parser reads, what `LawName::as_str`
        // writes and what the schema lists.
        for (name, law, _) in LawName::NAMES {
            assert_eq!(LawName::try_from(toml::Value::String((*name).into())).unwrap(), *law);
            assert_eq!(law.as_str(), *name);
        }
        for (name, support, _) in SupportName::NAMES {
            assert_eq!(
                SupportName::try_from(toml::Value::String((*name).into())).unwrap(),
                *support
            );
        }
        let e = FeModelName::try_from(toml::Value::String("2d".into())).unwrap_err();
        assert_eq!(e, "\"2d\" is not one of \"planar\", \"3d\"");
        let schema = serde_json::to_value(Scene::schema()).unwrap();
        let methods = &schema["$defs"]["MethodName"]["enum"];
        assert_eq!(methods, &serde_json::json!(["auto", "modal", "fe"]));
    }
}
