//! The six primitive kinds: cylinder, truncated cone, sphere, cuboid, straight
//! generalized cylinder (SGC) and bent generalized cylinder (BGC), one file each.
//!
//! Every kind has
//! - a numeric state in model space (a struct such as [`Cylinder`]) with a flat parameter
//!   vector for the solver ([`Primitive::params`], [`Primitive::with_params`]);
//! - a [`Shape`], computed by one generic function for both `f64` and AD expressions
//!   ([`Real`]): its projected 2D curves (view-plane coordinates, see
//!   [`geom::projection`](crate::geom::projection)) that strokes are matched to,
//!   its 3D [`FeatureCurve`]s ([`Feature`]s) that relations refer to, and its internal constraints
//!   C_p (unit axes, orthonormal frames, positive sizes);
//! - a triangle mesh ([`Primitive::mesh`]) for display and export.
//!
//! Canonical frame: the axis of a cylinder, cone or SGC runs from its *bottom* end to its
//! *top* end; `center` is halfway. Sizes never go to zero: each kind states a positive
//! lower bound as an inequality constraint relative to the primitive's size.

mod bgc;
mod cone;
mod cuboid;
mod cylinder;
mod feature;
mod mesh;
mod sgc;
mod sphere;
mod validate;

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

pub use bgc::Bgc;
pub use cone::Cone;
pub use cuboid::Cuboid;
pub use cylinder::Cylinder;
pub use feature::{Axis, Feature};
pub use mesh::TriMesh;
pub use sgc::Sgc;
pub use sphere::Sphere;
pub use validate::{PrimitiveError, UNIT_TOLERANCE};

use crate::ad::{Real, Vec2, Vec3};

/// The kind of a primitive, as named in scripts and model files.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PrimitiveKind {
    /// A cylinder.
    Cylinder,
    /// A truncated cone.
    Cone,
    /// A sphere.
    Sphere,
    /// A box with an orthonormal frame.
    Cuboid,
    /// A straight generalized cylinder: straight axis, radius profile.
    Sgc,
    /// A bent generalized cylinder: planar curved spine, radius profile.
    Bgc,
}

impl PrimitiveKind {
    /// Every kind, in palette order.
    pub const ALL: [Self; 6] = [
        Self::Cylinder,
        Self::Cone,
        Self::Sphere,
        Self::Cuboid,
        Self::Sgc,
        Self::Bgc,
    ];

    /// The name used in files (`"cylinder"`, `"sgc"`, …).
    pub fn name(self) -> &'static str {
        match self {
            Self::Cylinder => "cylinder",
            Self::Cone => "cone",
            Self::Sphere => "sphere",
            Self::Cuboid => "cuboid",
            Self::Sgc => "sgc",
            Self::Bgc => "bgc",
        }
    }

    /// The kind called `name`, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }
}

/// Which stroke class a projected curve expects.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveClass {
    /// An end ellipse: matched to feature strokes.
    Feature,
    /// An outline of a side: matched to silhouette strokes.
    Silhouette,
    /// A box edge: matched to straight strokes of either class.
    Edge,
}

/// A 2D curve in view-plane coordinates over a scalar `T`.
#[derive(Clone, Debug, PartialEq)]
pub enum Curve2<T> {
    /// The ellipse `center + a·cos θ + b·sin θ` (a, b conjugate semi-diameters).
    Ellipse {
        /// The centre.
        center: Vec2<T>,
        /// The first semi-diameter.
        a: Vec2<T>,
        /// The second semi-diameter.
        b: Vec2<T>,
    },
    /// An open polyline (a segment has two points).
    Polyline(Vec<Vec2<T>>),
}

impl Curve2<f64> {
    /// Points along the curve: `n + 1` evenly in θ for an ellipse (closed: the last is the
    /// first), the vertices of a polyline.
    pub fn points(&self, n: usize) -> Vec<DVec2> {
        match self {
            Self::Ellipse { center, a, b } => {
                let (c, a, b) = (center.to_dvec2(), a.to_dvec2(), b.to_dvec2());
                let n = n.max(1);
                (0..=n)
                    .map(|k| {
                        let t = std::f64::consts::TAU * k as f64 / n as f64;
                        c + a * t.cos() + b * t.sin()
                    })
                    .collect()
            }
            Self::Polyline(points) => points.iter().map(|p| p.to_dvec2()).collect(),
        }
    }
}

/// A projected curve of a primitive with its role.
#[derive(Clone, Debug, PartialEq)]
pub struct ProjectedCurve<T> {
    /// A name for messages and overlays (`"top"`, `"left"`, `"edge 3"`, …).
    pub name: String,
    /// Which strokes it takes.
    pub class: CurveClass,
    /// Whether a person would draw it in this view (hidden box edges are not).
    pub visible: bool,
    /// The geometry.
    pub curve: Curve2<T>,
}

impl<T> ProjectedCurve<T> {
    /// A curve a person draws in every view (outlines and end ellipses).
    pub(crate) fn shown(name: &str, class: CurveClass, curve: Curve2<T>) -> Self {
        Self {
            name: name.to_owned(),
            class,
            visible: true,
            curve,
        }
    }
}

/// The geometry of a 3D feature curve, which relations refer to.
#[derive(Clone, Debug, PartialEq)]
pub enum FeatureGeometry<T> {
    /// A circle: an end of a cylinder, cone or generalized cylinder.
    Circle {
        /// The centre.
        center: Vec3<T>,
        /// The unit normal (along the primitive's axis, outwards at the top).
        normal: Vec3<T>,
        /// The radius.
        radius: T,
    },
    /// A rectangle: a face of a cuboid.
    Rectangle {
        /// The centre.
        center: Vec3<T>,
        /// The unit outward normal.
        normal: Vec3<T>,
        /// Half the extents along the face's two in-plane axes, with those axes.
        half_extents: [(Vec3<T>, T); 2],
    },
}

/// A feature curve of a primitive (an end, a sphere's outline or a box face) with its
/// geometry.
#[derive(Clone, Debug, PartialEq)]
pub struct FeatureCurve<T> {
    /// Which feature it is.
    pub feature: Feature,
    /// The geometry.
    pub geometry: FeatureGeometry<T>,
}

/// The geometry of a primitive at some parameters: projected curves, feature curves and
/// internal constraints.
#[derive(Clone, Debug, PartialEq)]
pub struct Shape<T> {
    /// The projected curves strokes are matched to.
    pub curves: Vec<ProjectedCurve<T>>,
    /// The 3D feature curves, in the order of [`PrimitiveKind::features`].
    pub features: Vec<FeatureCurve<T>>,
    /// Equality constraints c = 0 of the parameterisation, labelled.
    pub equalities: Vec<(&'static str, T)>,
    /// Inequality constraints g ≥ 0 (positive sizes), labelled.
    pub inequalities: Vec<(&'static str, T)>,
    /// Regularising residuals r whose squares are added to the objective with a small
    /// weight (smoothness of profiles and spines); empty for most kinds.
    pub regularizers: Vec<T>,
    /// Second differences of a bent tube's radii along its spine, unweighted: a fit holds
    /// its profile smooth by them as strongly as its [`crate::snap::Profile`] says. Empty
    /// for the other kinds.
    pub profile: Vec<T>,
    /// Residuals of a pull towards the least tilted pose, added (squared, with the
    /// regularisers' weight) only when no end ellipse is assigned: without an end's
    /// evidence the outlines alone do not tell how a bent tube's plane leans out of the
    /// view, and the least tilted reading is kept. Empty for most kinds.
    pub untilted: Vec<T>,
}

impl<T> Default for Shape<T> {
    fn default() -> Self {
        Self {
            curves: Vec::new(),
            features: Vec::new(),
            equalities: Vec::new(),
            inequalities: Vec::new(),
            regularizers: Vec::new(),
            profile: Vec::new(),
            untilted: Vec::new(),
        }
    }
}

/// Where and how big a primitive is dropped: the script's step or the palette's drag, in
/// sketch space (formats.md §2).
#[derive(Clone, Debug, PartialEq)]
pub struct Placement {
    /// The sketch point the primitive's centre projects to.
    pub at: DVec2,
    /// The 2D image direction from bottom to top (default up the page).
    pub axis: DVec2,
    /// Projected length along `axis`.
    pub length: Option<f64>,
    /// Apparent radius (half the apparent width).
    pub radius: Option<f64>,
    /// Cone bottom radius.
    pub radius_bottom: Option<f64>,
    /// Cone top radius.
    pub radius_top: Option<f64>,
    /// Rough apparent extents of a box.
    pub size: Option<[f64; 3]>,
}

impl Placement {
    /// Whether it gives no size at all: a drop the drawing sizes (see
    /// [`crate::snap::snap_at`]).
    pub fn is_unsized(&self) -> bool {
        self.length.is_none()
            && self.radius.is_none()
            && self.radius_bottom.is_none()
            && self.radius_top.is_none()
            && self.size.is_none()
    }

    /// The direction it gives: `None` for the default, up the page, which says nothing
    /// of the part (an unsized drop is then turned by the drawing).
    pub fn given_axis(&self) -> Option<DVec2> {
        (self.axis != Self::at(self.at).axis).then_some(self.axis)
    }

    /// A placement at `at` with every size defaulted.
    pub fn at(at: DVec2) -> Self {
        Self {
            at,
            axis: DVec2::new(0.0, -1.0),
            length: None,
            radius: None,
            radius_bottom: None,
            radius_top: None,
            size: None,
        }
    }
}

/// A primitive of any kind.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Primitive {
    /// A cylinder.
    Cylinder(Cylinder),
    /// A truncated cone.
    Cone(Cone),
    /// A sphere.
    Sphere(Sphere),
    /// A cuboid.
    Cuboid(Cuboid),
    /// A straight generalized cylinder.
    Sgc(Sgc),
    /// A bent generalized cylinder.
    Bgc(Bgc),
}

/// Applies `$body` to the inner struct of every variant.
macro_rules! each_kind {
    ($value:expr, $inner:ident => $body:expr) => {
        match $value {
            Primitive::Cylinder($inner) => $body,
            Primitive::Cone($inner) => $body,
            Primitive::Sphere($inner) => $body,
            Primitive::Cuboid($inner) => $body,
            Primitive::Sgc($inner) => $body,
            Primitive::Bgc($inner) => $body,
        }
    };
}

/// Default apparent size of a new primitive, as a fraction of the sketch's larger extent.
pub const DEFAULT_SIZE_FRACTION: f64 = 0.15;

impl Primitive {
    /// A primitive of `kind` from a placement, in model space, lying in the view plane
    /// (depth 0) and facing the viewer as the palette drops it. `default_size` is the
    /// apparent size used for sizes the placement leaves out.
    pub fn from_placement(kind: PrimitiveKind, placement: &Placement, default_size: f64) -> Self {
        match kind {
            PrimitiveKind::Cylinder => {
                Self::Cylinder(Cylinder::from_placement(placement, default_size))
            }
            PrimitiveKind::Cone => Self::Cone(Cone::from_placement(placement, default_size)),
            PrimitiveKind::Sphere => Self::Sphere(Sphere::from_placement(placement, default_size)),
            PrimitiveKind::Cuboid => Self::Cuboid(Cuboid::from_placement(placement, default_size)),
            PrimitiveKind::Sgc => Self::Sgc(Sgc::from_placement(placement, default_size)),
            PrimitiveKind::Bgc => Self::Bgc(Bgc::from_placement(placement, default_size)),
        }
    }

    /// The kind.
    pub fn kind(&self) -> PrimitiveKind {
        match self {
            Self::Cylinder(_) => PrimitiveKind::Cylinder,
            Self::Cone(_) => PrimitiveKind::Cone,
            Self::Sphere(_) => PrimitiveKind::Sphere,
            Self::Cuboid(_) => PrimitiveKind::Cuboid,
            Self::Sgc(_) => PrimitiveKind::Sgc,
            Self::Bgc(_) => PrimitiveKind::Bgc,
        }
    }

    /// The flat parameter vector (the layout is documented on each kind).
    pub fn params(&self) -> Vec<f64> {
        each_kind!(self, p => p.params())
    }

    /// The same primitive with new parameters (of the same length as
    /// [`Primitive::params`]); frames and axes are re-normalised.
    #[must_use]
    pub fn with_params(&self, x: &[f64]) -> Self {
        match self {
            Self::Cylinder(p) => Self::Cylinder(p.with_params(x)),
            Self::Cone(p) => Self::Cone(p.with_params(x)),
            Self::Sphere(p) => Self::Sphere(p.with_params(x)),
            Self::Cuboid(p) => Self::Cuboid(p.with_params(x)),
            Self::Sgc(p) => Self::Sgc(p.with_params(x)),
            Self::Bgc(p) => Self::Bgc(p.with_params(x)),
        }
    }

    /// The shape at parameters `x` (for `f64`: [`Primitive::params`] gives the current
    /// one; for expressions: the solver's variables).
    pub fn shape<T: Real>(&self, x: &[T]) -> Shape<T> {
        each_kind!(self, p => p.shape(x))
    }

    /// The shape at the current parameters.
    pub fn current_shape(&self) -> Shape<f64> {
        self.shape(&self.params())
    }

    /// The model-space centre.
    pub fn center(&self) -> DVec3 {
        each_kind!(self, p => p.center())
    }

    /// A characteristic size: the larger of the primitive's length and diameter (its
    /// largest extent).
    pub fn size(&self) -> f64 {
        each_kind!(self, p => p.size())
    }

    /// The primitive moved by `offset` and scaled by `factor` about the origin: model
    /// → normalised frame and back.
    #[must_use]
    pub fn transformed(&self, offset: DVec3, factor: f64) -> Self {
        match self {
            Self::Cylinder(p) => Self::Cylinder(p.transformed(offset, factor)),
            Self::Cone(p) => Self::Cone(p.transformed(offset, factor)),
            Self::Sphere(p) => Self::Sphere(p.transformed(offset, factor)),
            Self::Cuboid(p) => Self::Cuboid(p.transformed(offset, factor)),
            Self::Sgc(p) => Self::Sgc(p.transformed(offset, factor)),
            Self::Bgc(p) => Self::Bgc(p.transformed(offset, factor)),
        }
    }

    /// The primitive reflected in the view-parallel plane through its centre (depth z ↦
    /// 2·c_z − z). Its projection, and so its fit to the strokes, is the same: an
    /// orthographic drawing cannot tell the two apart, and relations decide between
    /// them.
    #[must_use]
    pub fn mirrored_in_depth(&self) -> Self {
        let depth = self.center().z;
        let point = |p: DVec3| DVec3::new(p.x, p.y, 2.0 * depth - p.z);
        let dir = |d: DVec3| DVec3::new(d.x, d.y, -d.z);
        let mut out = self.clone();
        match &mut out {
            Self::Cylinder(p) => p.axis = dir(p.axis),
            Self::Cone(p) => p.axis = dir(p.axis),
            Self::Sgc(p) => p.axis = dir(p.axis),
            Self::Sphere(_) => {}
            // M·R·M with M = diag(1, 1, −1) is the rotation of quaternion (−x, −y, z, w);
            // its columns are the reflected axes up to sign, which a box does not mind.
            Self::Cuboid(p) => {
                p.rotation = glam::DQuat::from_xyzw(
                    -p.rotation.x,
                    -p.rotation.y,
                    p.rotation.z,
                    p.rotation.w,
                );
            }
            Self::Bgc(p) => {
                for s in &mut p.spine {
                    *s = point(*s);
                }
                p.plane_normal = dir(p.plane_normal);
            }
        }
        out
    }

    /// A triangle mesh with about `segments` segments around each circle.
    pub fn mesh(&self, segments: usize) -> TriMesh {
        each_kind!(self, p => p.mesh(segments.max(3)))
    }

    /// The feature curves this primitive has (those of its kind).
    pub fn features(&self) -> &'static [Feature] {
        self.kind().features()
    }

    /// Whether every parameter is finite.
    pub fn is_finite(&self) -> bool {
        self.params().iter().all(|v| v.is_finite())
    }
}

/// The point or direction stored at `x[i..i + 3]` of a parameter vector.
pub(crate) fn vec3_at(x: &[f64], i: usize) -> DVec3 {
    DVec3::new(x[i], x[i + 1], x[i + 2])
}

/// The vector expression stored at `x[i..i + 3]` of a parameter vector.
pub(crate) fn vec3_expr_at<T: Real>(x: &[T], i: usize) -> Vec3<T> {
    Vec3::new(x[i], x[i + 1], x[i + 2])
}

/// The quaternion (w, x, y, z) stored at `x[i..i + 4]` of a parameter vector.
pub(crate) fn quaternion_at<T: Copy>(x: &[T], i: usize) -> [T; 4] {
    [x[i], x[i + 1], x[i + 2], x[i + 3]]
}

/// The two unit vectors spanning the plane ⊥ `axis` used to draw its circles:
/// `w` horizontal (z = 0) and `k = axis × w`. Their view-plane parts are the projected
/// ellipse's semi-diameters per unit radius: |w_xy| = 1 and |k_xy| = |axis_z|.
///
/// `ρ = √(aₓ² + a_y²)` is regularised by 1e-9 so that an axis pointing straight at the
/// viewer (where the basis is arbitrary) stays finite.
pub(crate) fn circle_basis<T: Real>(axis: Vec3<T>) -> (Vec3<T>, Vec3<T>) {
    let rho = (axis.x.square() + axis.y.square() + 1e-18).sqrt();
    let zero = axis.x.lit(0.0);
    let w = Vec3::new(axis.y / rho, -axis.x / rho, zero);
    let k = axis.cross(w);
    (w, k)
}

/// The rotation matrix columns of the quaternion (w, x, y, z), assumed unit.
pub(crate) fn quaternion_columns<T: Real>(q: [T; 4]) -> [Vec3<T>; 3] {
    let [w, x, y, z] = q;
    let one = w.lit(1.0);
    let two = |v: T| v * 2.0;
    [
        Vec3::new(
            one - two(y * y + z * z),
            two(x * y + w * z),
            two(x * z - w * y),
        ),
        Vec3::new(
            two(x * y - w * z),
            one - two(x * x + z * z),
            two(y * z + w * x),
        ),
        Vec3::new(
            two(x * z + w * y),
            two(y * z - w * x),
            one - two(x * x + y * y),
        ),
    ]
}

/// The projected ellipse of the circle (centre, unit normal, radius).
pub(crate) fn circle_ellipse<T: Real>(center: Vec3<T>, normal: Vec3<T>, radius: T) -> Curve2<T> {
    let (w, k) = circle_basis(normal);
    Curve2::Ellipse {
        center: center.xy(),
        a: w.xy() * radius,
        b: k.xy() * radius,
    }
}

/// The two contour points (right, left as seen by the viewer when the axis points up the
/// page) of the circle of radius `r` at `center` on a
/// surface of revolution about the unit `axis` whose radius changes by `slope` (dr/dh)
/// along it: where the surface normal e − slope·axis is perpendicular to the view.
///
/// With the basis of [`circle_basis`], e = α·w + β·k with β = −slope·a_z/ρ·(… ) reduced to
/// view-plane offsets: e_xy = ±α·(a_y, −aₓ)/ρ − slope·(a_z²/ρ²)·(aₓ, a_y), α = √(1 − β²),
/// β = slope·a_z/ρ. When no contour exists (looking down a cone) α is clamped at 0.
pub(crate) fn contour_points<T: Real>(
    center: Vec3<T>,
    axis: Vec3<T>,
    r: T,
    slope: T,
) -> [Vec2<T>; 2] {
    let rho2 = axis.x.square() + axis.y.square() + 1e-18;
    let rho = rho2.sqrt();
    let beta = slope * axis.z / rho;
    let alpha = (-beta.square() + 1.0).max(beta.lit(1e-12)).sqrt();
    let side = Vec2::new(axis.y / rho, -axis.x / rho) * alpha;
    let along = Vec2::new(axis.x, axis.y) * (slope * axis.z.square() / rho2);
    let c = center.xy();
    [c + (side - along) * r, c + (-side - along) * r]
}

/// The tilt towards the viewer that a dropped cylinder, cone or SGC starts with: people
/// draw such objects from a little above, so their ends show as ellipses rather than
/// lines, and a starting tilt lets the end ellipses be matched from the first frame.
pub const DROP_TILT_DEGREES: f64 = 20.0;

/// The starting axis and true length of a dropped solid of revolution: the placement's
/// image direction tilted by [`DROP_TILT_DEGREES`] towards the viewer, and the projected
/// length divided by the cosine of that tilt.
pub(crate) fn dropped_axis(p: &Placement, default_size: f64) -> (DVec3, f64) {
    let image = crate::geom::projection::model_direction_from_sketch(p.axis).unwrap_or(DVec3::Y);
    let tilt = DROP_TILT_DEGREES.to_radians();
    let axis = (image * tilt.cos() + DVec3::Z * tilt.sin()).normalize();
    let length = p.length.unwrap_or(default_size).abs().max(1e-9) / tilt.cos();
    (axis, length)
}

/// Sample count of the profiles of generalized cylinders.
pub const PROFILE_SAMPLES: usize = 8;

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::{circle_ellipse, contour_points, Curve2};
    use crate::ad::Vec3;

    #[test]
    fn a_circle_facing_the_viewer_projects_to_a_circle() {
        let c = Vec3::from_dvec3(DVec3::new(1.0, 2.0, 3.0));
        let n = Vec3::from_dvec3(DVec3::new(0.0, 0.6, 0.8));
        let Curve2::Ellipse { center, a, b } = circle_ellipse(c, n, 2.0) else {
            panic!("an ellipse")
        };
        assert!((center.x - 1.0).abs() < 1e-12 && (center.y - 2.0).abs() < 1e-12);
        assert!(
            (a.norm() - 2.0).abs() < 1e-9,
            "major semi-axis is the radius"
        );
        assert!((b.norm() - 1.6).abs() < 1e-9, "minor is r·|n_z|");
        assert!(a.dot(b).abs() < 1e-12, "orthogonal semi-axes");
    }

    #[test]
    fn cylinder_contours_are_offset_by_the_radius() {
        let c = Vec3::from_dvec3(DVec3::ZERO);
        let axis = Vec3::from_dvec3(DVec3::new(0.0, 0.8, 0.6));
        let [l, r] = contour_points(c, axis, 2.0, 0.0);
        assert!((l.x - 2.0).abs() < 1e-9 && l.y.abs() < 1e-9, "{l:?}");
        assert!((r.x + 2.0).abs() < 1e-9 && r.y.abs() < 1e-9, "{r:?}");
    }

    #[test]
    fn cone_contours_are_tangent_to_the_end_ellipses() {
        // A cone seen from above at an angle: the contour points of each end lie on the
        // projected ellipse of that end, and the contour line is tangent there.
        let axis = DVec3::new(0.3, 0.8, 0.52).normalize();
        let (rb, rt, l) = (3.0, 1.0, 5.0);
        let slope = (rt - rb) / l;
        let bottom = DVec3::new(0.5, -1.0, 0.2);
        let top = bottom + axis * l;
        let a = Vec3::from_dvec3(axis);
        let pb = contour_points(Vec3::from_dvec3(bottom), a, rb, slope);
        let pt = contour_points(Vec3::from_dvec3(top), a, rt, slope);
        for (end, r, pts) in [(bottom, rb, pb), (top, rt, pt)] {
            let Curve2::Ellipse {
                center,
                a: ea,
                b: eb,
            } = circle_ellipse(Vec3::from_dvec3(end), a, r)
            else {
                panic!("an ellipse")
            };
            for p in pts {
                // On the ellipse: p − c = ea·cos t + eb·sin t for some t.
                let d = (p - center).to_dvec2();
                let m = glam::DMat2::from_cols(ea.to_dvec2(), eb.to_dvec2());
                let cs = m.inverse() * d;
                assert!((cs.length() - 1.0).abs() < 1e-9, "on the ellipse: {cs:?}");
            }
        }
        // Tangency: the contour line direction is parallel to the ellipse tangent.
        for side in 0..2 {
            let dir = (pt[side] - pb[side]).to_dvec2();
            let Curve2::Ellipse {
                center,
                a: ea,
                b: eb,
            } = circle_ellipse(Vec3::from_dvec3(bottom), a, rb)
            else {
                panic!("an ellipse")
            };
            let m = glam::DMat2::from_cols(ea.to_dvec2(), eb.to_dvec2());
            let cs = m.inverse() * (pb[side] - center).to_dvec2();
            let tangent = m * glam::DVec2::new(-cs.y, cs.x);
            assert!(dir.perp_dot(tangent).abs() < 1e-9 * dir.length() * tangent.length());
        }
    }

    #[test]
    fn a_mirror_in_depth_projects_alike() {
        use super::{Cone, Cuboid, Primitive, Sgc, Sphere};
        use glam::DQuat;
        let parts = [
            Primitive::Cone(Cone {
                center: DVec3::new(1.0, 2.0, 3.0),
                axis: DVec3::new(0.3, 0.8, 0.52).normalize(),
                length: 5.0,
                radius_bottom: 2.0,
                radius_top: 1.0,
            }),
            Primitive::Sgc(Sgc {
                center: DVec3::new(-1.0, 0.5, -2.0),
                axis: DVec3::new(-0.2, 0.9, -0.4).normalize(),
                length: 6.0,
                radii: vec![1.0, 1.5, 1.2, 0.8],
            }),
            Primitive::Sphere(Sphere {
                center: DVec3::new(0.0, 1.0, 4.0),
                radius: 2.0,
            }),
            Primitive::Cuboid(Cuboid {
                center: DVec3::new(2.0, -1.0, 0.5),
                rotation: DQuat::from_euler(glam::EulerRot::XYZ, 0.4, -0.7, 0.2),
                size: DVec3::new(1.0, 2.0, 3.0),
            }),
        ];
        for p in parts {
            let m = p.mirrored_in_depth();
            assert!((m.center() - p.center()).length() < 1e-12);
            let points = |q: &Primitive| -> Vec<Vec<glam::DVec2>> {
                let mut curves: Vec<Vec<glam::DVec2>> = q
                    .current_shape()
                    .curves
                    .iter()
                    .map(|c| c.curve.points(16))
                    .collect();
                // A box's edges may come in another order; compare them as sets.
                for c in &mut curves {
                    c.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
                }
                curves.sort_by(|a, b| a[0].x.total_cmp(&b[0].x).then(a[0].y.total_cmp(&b[0].y)));
                curves
            };
            for (a, b) in points(&p).iter().zip(points(&m).iter()) {
                for (u, v) in a.iter().zip(b) {
                    assert!((*u - *v).length() < 1e-9, "{:?}: {u} vs {v}", p.kind());
                }
            }
            assert_eq!(m.mirrored_in_depth().params().len(), p.params().len());
        }
    }
}
