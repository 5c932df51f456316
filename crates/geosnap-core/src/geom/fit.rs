//! Least-squares fits of lines, circles and ellipses to 2D points.
//!
//! These fits classify strokes ([`crate::sketch::classify`]) and initialise
//! primitives from strokes. All three work in a *normalised frame*: the points are
//! translated to their centroid and divided by their largest distance from it, so the
//! sums of squares and products stay near 1 whatever the sketch's units (a drawing in
//! pixels near (3000, 2000), one in metres near 1e-3, or coordinates near 1e150 all fit
//! the same way), and the result is mapped back at the end.
//!
//! Every fit returns `None` rather than a value with NaN or ∞ in it: when there are too
//! few points, when a point is not finite, when the points coincide (or are collinear,
//! for circles and ellipses), or when the normalised frame itself overflows.
//!
//! - [`fit_line`]: principal component analysis (total least squares).
//! - [`fit_circle`]: Kåsa's algebraic fit, refined by Gauss–Newton on geometric distance.
//! - [`fit_ellipse`]: Fitzgibbon, Pilu and Fisher's direct least-squares ellipse fit
//!   ("Direct least square fitting of ellipses", IEEE PAMI 21(5), 1999), in the
//!   numerically stable form of Halíř and Flusser ("Numerically stable direct least
//!   squares fitting of ellipses", WSCG 1998).
//! - [`refine_ellipse`]: Levenberg–Marquardt on the geometric distances, which removes
//!   the algebraic fit's bias on noisy partial arcs.
//!
//! [`Ellipse2`] also answers the geometric questions the classifier needs: the true
//! Euclidean distance from a point ([`Ellipse2::distance`]), points by parameter
//! ([`Ellipse2::point_at`]) and the arc a set of points covers
//! ([`Ellipse2::angular_span`]).

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use glam::DVec2;

/// A straight line fitted to points by principal component analysis.
///
/// The line passes through [`centroid`](Self::centroid) along the unit
/// [`direction`](Self::direction); the points' projections onto it lie in
/// `t_min..=t_max` (signed distances from the centroid along the direction).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line2 {
    /// The mean of the points; a point of the line.
    pub centroid: DVec2,
    /// Unit direction of the line, oriented from the first point towards the last one
    /// (so `t` grows along a stroke drawn roughly straight).
    pub direction: DVec2,
    /// The smallest projection `(p − centroid)·direction` over the points (≤ 0).
    pub t_min: f64,
    /// The largest projection `(p − centroid)·direction` over the points (≥ 0).
    pub t_max: f64,
    /// Root mean square of the points' perpendicular distances to the line, in the
    /// points' units: `sqrt(mean(((p − centroid)·normal)²))`.
    pub rms_residual: f64,
}

impl Line2 {
    /// The unit normal, the direction turned by +90°: `(−d.y, d.x)`.
    pub fn normal(&self) -> DVec2 {
        self.direction.perp()
    }

    /// The point at signed distance `t` from the centroid along the direction.
    pub fn point_at(&self, t: f64) -> DVec2 {
        self.centroid + t * self.direction
    }

    /// The projection of the first extreme point onto the line, `point_at(t_min)`.
    pub fn start(&self) -> DVec2 {
        self.point_at(self.t_min)
    }

    /// The projection of the last extreme point onto the line, `point_at(t_max)`.
    pub fn end(&self) -> DVec2 {
        self.point_at(self.t_max)
    }

    /// The extent of the points along the line, `t_max − t_min`.
    pub fn length(&self) -> f64 {
        self.t_max - self.t_min
    }

    /// The perpendicular distance from `p` to the (infinite) line.
    pub fn distance(&self, p: DVec2) -> f64 {
        (p - self.centroid).dot(self.normal()).abs()
    }
}

/// A circle fitted to points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Circle2 {
    /// The centre.
    pub center: DVec2,
    /// The radius (> 0).
    pub radius: f64,
    /// Root mean square of the geometric residuals `|p − center| − radius`, in the
    /// points' units.
    pub rms_residual: f64,
}

impl Circle2 {
    /// The Euclidean distance from `p` to the circle, `||p − center| − radius|`.
    pub fn distance(&self, p: DVec2) -> f64 {
        (p.distance(self.center) - self.radius).abs()
    }

    /// The point at angle `theta` (radians, from +x towards +y).
    pub fn point_at(&self, theta: f64) -> DVec2 {
        self.center + self.radius * DVec2::from_angle(theta)
    }
}

/// An ellipse: `point_at(θ) = center + a·cos θ·u + b·sin θ·v`, where `u` is the unit
/// major axis at [`angle`](Self::angle) from +x, `v = u.perp()`, `a` the semi-major and
/// `b` the semi-minor axis. `θ` is the *eccentric anomaly* (the parametric angle), not
/// the polar angle of the point seen from the centre; the two agree on circles and at
/// the four vertices.
///
/// [`fit_ellipse`] returns `semi_major ≥ semi_minor > 0` and `angle ∈ (−π/2, π/2]`.
/// The methods also accept hand-built values with the semi-axes swapped or zero (a
/// segment, or a point).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ellipse2 {
    /// The centre.
    pub center: DVec2,
    /// The semi-axis along [`angle`](Self::angle) (the larger one, for fitted ellipses).
    pub semi_major: f64,
    /// The semi-axis perpendicular to it.
    pub semi_minor: f64,
    /// The angle of the major axis from +x towards +y, in radians.
    pub angle: f64,
}

/// An arc of an ellipse's parameter circle: `θ` from [`start`](Self::start) to
/// `start + sweep`, counter-clockwise in the parameter (towards +v from +u).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AngularSpan {
    /// The parameter where the arc begins, in `(−π, π]`.
    pub start: f64,
    /// The parameter range covered, in `[0, 2π]`.
    pub sweep: f64,
}

impl AngularSpan {
    /// The parameter where the arc ends, `start + sweep` (may exceed π).
    pub fn end(&self) -> f64 {
        self.start + self.sweep
    }
}

/// The point of an ellipse closest to a given point: its parameter `θ`, `sin θ`,
/// `cos θ` and the point itself ([`Ellipse2::closest_point`]).
#[derive(Clone, Copy, Debug)]
struct Foot {
    theta: f64,
    sin: f64,
    cos: f64,
    point: DVec2,
}

impl Ellipse2 {
    /// The unit major axis `u = (cos angle, sin angle)`.
    pub fn major_axis(&self) -> DVec2 {
        DVec2::from_angle(self.angle)
    }

    /// The unit minor axis `v = u.perp()`.
    pub fn minor_axis(&self) -> DVec2 {
        self.major_axis().perp()
    }

    /// The point with eccentric anomaly `theta`:
    /// `center + semi_major·cos θ·u + semi_minor·sin θ·v`.
    pub fn point_at(&self, theta: f64) -> DVec2 {
        let (s, c) = theta.sin_cos();
        let u = self.major_axis();
        self.center + self.semi_major * c * u + self.semi_minor * s * u.perp()
    }

    /// `p` in the ellipse's own frame: `((p − center)·u, (p − center)·v)`.
    pub fn to_local(&self, p: DVec2) -> DVec2 {
        let d = p - self.center;
        let u = self.major_axis();
        DVec2::new(d.dot(u), d.dot(u.perp()))
    }

    /// The point of the ellipse closest to `p`, as `(θ, point)` with `θ ∈ (−π, π]`.
    ///
    /// Method: by symmetry `p` is reflected into the first quadrant of the ellipse's frame,
    /// where the closest point has `θ ∈ [0, π/2]` and is a root of
    /// `f(θ) = (a² − b²)·sin θ·cos θ − x·a·sin θ + y·b·cos θ` (the offset `p − point(θ)`
    /// is normal to the ellipse); `f(0) ≥ 0 ≥ f(π/2)` brackets a root. The initial guess
    /// is three steps of the evolute iteration (each step treats the ellipse locally as its
    /// osculating circle), which lands near the right root even for points inside the
    /// ellipse, where `f` has several; then safeguarded Newton steps on `θ` (bisection when
    /// a step leaves the bracket) converge in a few iterations. The two vertices of the
    /// quadrant are compared as well and the nearest candidate wins.
    ///
    /// Degenerate cases: a circle needs no special case; a very flat ellipse
    /// (`b ≤ 1e−12·a`) is treated as the segment between its vertices, and a zero-size
    /// one as its centre (`θ` is then the polar angle of `p`).
    pub fn closest_point(&self, p: DVec2) -> (f64, DVec2) {
        let foot = self.foot(self.major_axis(), p);
        (foot.theta, foot.point)
    }

    /// [`Ellipse2::closest_point`] with the unit major axis `u` given (computed once for
    /// many points), and the sine and cosine of the parameter.
    fn foot(&self, u: DVec2, p: DVec2) -> Foot {
        let d = p - self.center;
        let v = u.perp();
        let local = DVec2::new(d.dot(u), d.dot(v));
        let a = self.semi_major.abs();
        let b = self.semi_minor.abs();
        let theta = if a >= b {
            closest_theta(a, b, local.x, local.y)
        } else {
            // Swap the roles of the axes: x = a cos θ, y = b sin θ becomes
            // y = b cos θ', x = a sin θ' with θ = π/2 − θ'.
            wrap_angle(FRAC_PI_2 - closest_theta(b, a, local.y, local.x))
        };
        let (sin, cos) = theta.sin_cos();
        Foot {
            theta,
            sin,
            cos,
            point: self.center + self.semi_major * cos * u + self.semi_minor * sin * v,
        }
    }

    /// The Euclidean distance from `p` to the ellipse (the curve, not the filled disk).
    ///
    /// See [`Ellipse2::closest_point`] for the method; accurate to rounding for every
    /// point, inside or outside, circles and very flat ellipses included.
    pub fn distance(&self, p: DVec2) -> f64 {
        p.distance(self.closest_point(p).1)
    }

    /// The root mean square of the points' Euclidean distances to the ellipse
    /// (0 for no points).
    pub fn rms_distance(&self, points: &[DVec2]) -> f64 {
        self.rms_distance_and_span(points).0
    }

    /// [`Ellipse2::rms_distance`] and [`Ellipse2::angular_span`] of the same points, with
    /// each point's closest point found once for both.
    pub fn rms_distance_and_span(&self, points: &[DVec2]) -> (f64, Option<AngularSpan>) {
        if points.is_empty() {
            return (0.0, None);
        }
        let u = self.major_axis();
        let mut thetas = Vec::with_capacity(points.len());
        let mut sum = 0.0;
        for &p in points {
            let foot = self.foot(u, p);
            sum += p.distance(foot.point).powi(2);
            thetas.push(foot.theta);
        }
        ((sum / points.len() as f64).sqrt(), span_of(thetas))
    }

    /// The arc of the ellipse that `points` cover: each point is mapped to the parameter
    /// of its closest point on the ellipse, and the covered arc is the circle of
    /// parameters minus the largest gap between consecutive parameters (in sorted order,
    /// ignoring the order of the points). `None` for no points; a single point gives a
    /// sweep of 0; points all round the ellipse give a sweep close to 2π.
    ///
    /// The sweep is measured in the eccentric anomaly, which on a flat ellipse changes
    /// fastest near the ends of the minor axis: a quarter of the parameter circle is a
    /// quarter of the ellipse between two vertices, not a quarter of its length.
    pub fn angular_span(&self, points: &[DVec2]) -> Option<AngularSpan> {
        self.rms_distance_and_span(points).1
    }
}

/// The arc of parameters `thetas` cover (see [`Ellipse2::angular_span`]).
fn span_of(mut thetas: Vec<f64>) -> Option<AngularSpan> {
    thetas.sort_by(f64::total_cmp);
    let (&first, &last) = (thetas.first()?, thetas.last()?);
    // The wrap-around gap first, then the gaps between neighbours.
    let mut gap = first + TAU - last;
    let mut start = first;
    for w in thetas.windows(2) {
        let g = w[1] - w[0];
        if g > gap {
            gap = g;
            start = w[1];
        }
    }
    Some(AngularSpan {
        start,
        sweep: (TAU - gap).clamp(0.0, TAU),
    })
}

/// Fits a straight line to `points` by principal component analysis (total least
/// squares): the line through the centroid along the eigenvector of the largest
/// eigenvalue of the points' covariance matrix; its direction angle is
/// `φ = ½·atan2(2·Sxy, Sxx − Syy)` in terms of the centred second moments.
///
/// `None` for fewer than two points, a non-finite point, or points that all coincide.
pub fn fit_line(points: &[DVec2]) -> Option<Line2> {
    if points.len() < 2 {
        return None;
    }
    let frame = Frame::new(points)?;
    let n = points.len() as f64;
    let local: Vec<DVec2> = points.iter().map(|&p| frame.to_local(p)).collect();
    let mean = local.iter().copied().sum::<DVec2>() / n;
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for q in &local {
        let d = *q - mean;
        sxx += d.x * d.x;
        sxy += d.x * d.y;
        syy += d.y * d.y;
    }
    if sxx + syy <= 0.0 {
        return None;
    }
    let phi = 0.5 * f64::atan2(2.0 * sxy, sxx - syy);
    let mut direction = DVec2::from_angle(phi);
    let (Some(first), Some(last)) = (local.first(), local.last()) else {
        return None;
    };
    if (*last - *first).dot(direction) < 0.0 {
        direction = -direction;
    }
    let normal = direction.perp();
    let (mut t_min, mut t_max, mut sum_r2) = (f64::INFINITY, f64::NEG_INFINITY, 0.0);
    for q in &local {
        let d = *q - mean;
        let t = d.dot(direction);
        t_min = t_min.min(t);
        t_max = t_max.max(t);
        sum_r2 += d.dot(normal).powi(2);
    }
    let line = Line2 {
        centroid: frame.to_world(mean),
        direction,
        t_min: t_min * frame.scale,
        t_max: t_max * frame.scale,
        rms_residual: (sum_r2 / n).sqrt() * frame.scale,
    };
    all_finite(&[
        line.centroid.x,
        line.centroid.y,
        line.t_min,
        line.t_max,
        line.rms_residual,
    ])
    .then_some(line)
}

/// Fits a circle to `points`: Kåsa's algebraic fit, then Gauss–Newton on the geometric
/// residuals.
///
/// Kåsa minimises `Σ(|p − c|² − r²)²`, which is linear in `c` once the points are
/// centred: with moments `Suu = Σu²`, `Suv = Σuv`, `Suuu = Σu³`, … of the centred
/// coordinates (u, v), the centre solves
/// `[Suu Suv; Suv Svv]·c = ½·[Suuu + Suvv; Svvv + Svuu]` and `r² = |c|² + (Suu + Svv)/n`.
/// It is exact on noise-free points but biased towards small circles on short noisy
/// arcs, so up to eight Gauss–Newton steps then minimise `Σ(|p − c| − r)²`, each step
/// halved until the cost decreases.
///
/// `None` for fewer than three points, a non-finite point, or points that are
/// (numerically) collinear or coincident.
pub fn fit_circle(points: &[DVec2]) -> Option<Circle2> {
    if points.len() < 3 {
        return None;
    }
    let frame = Frame::new(points)?;
    let n = points.len() as f64;
    let local: Vec<DVec2> = points.iter().map(|&p| frame.to_local(p)).collect();
    let (center, radius) = kasa_circle(&local)?;
    let (center, radius, current) = refine_circle(&local, center, radius);
    let circle = Circle2 {
        center: frame.to_world(center),
        radius: radius * frame.scale,
        rms_residual: (current / n).sqrt() * frame.scale,
    };
    (all_finite(&[
        circle.center.x,
        circle.center.y,
        circle.radius,
        circle.rms_residual,
    ]) && circle.radius > 0.0)
        .then_some(circle)
}

/// Kåsa's algebraic circle through `local` points (see [`fit_circle`]): its centre and
/// radius, or `None` when the points are (numerically) collinear.
fn kasa_circle(local: &[DVec2]) -> Option<(DVec2, f64)> {
    let n = local.len() as f64;
    let mean = local.iter().copied().sum::<DVec2>() / n;
    let (mut suu, mut suv, mut svv, mut ru, mut rv) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for q in local {
        let d = *q - mean;
        let r2 = d.length_squared();
        suu += d.x * d.x;
        suv += d.x * d.y;
        svv += d.y * d.y;
        ru += 0.5 * d.x * r2;
        rv += 0.5 * d.y * r2;
    }
    let det = suu * svv - suv * suv;
    // Collinear points make the moment matrix singular; the relative test also rejects
    // circles larger than about 1e7 times the spread of the points.
    if !(det > 1e-14 * (suu + svv).powi(2)) {
        return None;
    }
    let c = DVec2::new(ru * svv - rv * suv, rv * suu - ru * suv) / det;
    Some((mean + c, (c.length_squared() + (suu + svv) / n).sqrt()))
}

/// Up to eight Gauss–Newton steps on the geometric residuals `|q − c| − r` of `local`
/// points from the circle (`center`, `radius`), each halved until the cost decreases
/// (see [`fit_circle`]). Returns the centre, the radius and the sum of squared
/// residuals.
fn refine_circle(local: &[DVec2], mut center: DVec2, mut radius: f64) -> (DVec2, f64, f64) {
    let cost = |center: DVec2, radius: f64| -> f64 {
        local
            .iter()
            .map(|q| (q.distance(center) - radius).powi(2))
            .sum::<f64>()
    };
    let mut current = cost(center, radius);
    for _ in 0..8 {
        // Normal equations JᵀJ·δ = −Jᵀρ with ρᵢ = |qᵢ − c| − r and
        // ∂ρᵢ/∂c = −(qᵢ − c)/|qᵢ − c|, ∂ρᵢ/∂r = −1.
        let mut jtj = [[0.0; 3]; 3];
        let mut jtr = [0.0; 3];
        for q in local {
            let d = *q - center;
            let len = d.length();
            if len <= 0.0 {
                continue;
            }
            let row = [-d.x / len, -d.y / len, -1.0];
            let rho = len - radius;
            for i in 0..3 {
                jtr[i] -= row[i] * rho;
                for j in 0..3 {
                    jtj[i][j] += row[i] * row[j];
                }
            }
        }
        let Some(delta) = solve3(jtj, jtr) else {
            break;
        };
        let mut step = 1.0;
        let mut improved = false;
        for _ in 0..8 {
            let c2 = center + step * DVec2::new(delta[0], delta[1]);
            let r2 = radius + step * delta[2];
            let trial = cost(c2, r2);
            if r2 > 0.0 && trial < current {
                center = c2;
                radius = r2;
                current = trial;
                improved = true;
                break;
            }
            step *= 0.5;
        }
        let size = delta[0].abs() + delta[1].abs() + delta[2].abs();
        if !improved || size * step < 1e-15 * (1.0 + radius) {
            break;
        }
    }
    (center, radius, current)
}

/// Fits an ellipse to `points` by the direct least-squares method of Fitzgibbon, Pilu and
/// Fisher, in Halíř and Flusser's numerically stable form.
///
/// The conic `F(x, y) = a·x² + b·xy + c·y² + d·x + e·y + f` with coefficient vector
/// `(a₁; a₂) = ((a, b, c); (d, e, f))` minimises the algebraic distance `Σ F(pᵢ)²` subject
/// to the ellipse constraint `4ac − b² = 1`. With the design matrices `D₁ = [x² xy y²]`
/// and `D₂ = [x y 1]` and scatter blocks `S₁ = D₁ᵀD₁`, `S₂ = D₁ᵀD₂`, `S₃ = D₂ᵀD₂`,
/// eliminating `a₂ = T·a₁`, `T = −S₃⁻¹S₂ᵀ`, leaves the 3×3 generalised eigenproblem
/// `M·a₁ = λ·C₁·a₁` with the reduced scatter `M = S₁ + S₂T` (symmetric positive
/// semi-definite) and `C₁ = [0 0 2; 0 −1 0; 2 0 0]`. Its eigenvalues are the (real) roots
/// of the cubic `det(M − λC₁) = 0`, solved in closed form and polished by Newton; each
/// eigenvector is the cross product of two rows of `M − λC₁`. Exactly one eigenvector has
/// `4ac − b² > 0` in exact arithmetic; should rounding leave several, the one with the
/// smallest `a₁ᵀMa₁ / a₁ᵀC₁a₁` wins. The conic is finally converted to centre, semi-axes
/// and angle (see [`Ellipse2`]).
///
/// The points are normalised first (centroid at the origin, largest distance 1), which
/// the method needs: with raw pixel coordinates the fourth-order moments in `S₁` span
/// twelve orders of magnitude.
///
/// This is an algebraic fit: exact for points on an ellipse, and with noise slightly
/// biased towards smaller ellipses on short arcs. Because of the constraint the result
/// is always an ellipse; points that lie on a hyperbola or a line get the nearest
/// ellipse, which can fit badly, so check [`Ellipse2::rms_distance`].
///
/// `None` for fewer than five points, a non-finite point, collinear or coincident
/// points, or when rounding leaves no real ellipse.
pub fn fit_ellipse(points: &[DVec2]) -> Option<Ellipse2> {
    if points.len() < 5 {
        return None;
    }
    let frame = Frame::new(points)?;
    let mut s1 = [[0.0; 3]; 3];
    let mut s2 = [[0.0; 3]; 3];
    let mut s3 = [[0.0; 3]; 3];
    for &p in points {
        let q = frame.to_local(p);
        let d1 = [q.x * q.x, q.x * q.y, q.y * q.y];
        let d2 = [q.x, q.y, 1.0];
        for i in 0..3 {
            for j in 0..3 {
                s1[i][j] += d1[i] * d1[j];
                s2[i][j] += d1[i] * d2[j];
                s3[i][j] += d2[i] * d2[j];
            }
        }
    }
    // T = −S₃⁻¹·S₂ᵀ, column by column. S₃ is singular exactly when the points are
    // collinear; `solve3` rejects it with a relative pivot test.
    let mut t = [[0.0; 3]; 3];
    for col in 0..3 {
        let rhs = [-s2[col][0], -s2[col][1], -s2[col][2]];
        let x = solve3(s3, rhs)?;
        for row in 0..3 {
            t[row][col] = x[row];
        }
    }
    // M = S₁ + S₂·T, symmetrised against rounding.
    let mut m = s1;
    for i in 0..3 {
        for j in 0..3 {
            m[i][j] += (0..3).map(|k| s2[i][k] * t[k][j]).sum::<f64>();
        }
    }
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        let avg = 0.5 * (m[i][j] + m[j][i]);
        m[i][j] = avg;
        m[j][i] = avg;
    }
    let a1 = ellipse_eigenvector(&m)?;
    let a2 = [
        t[0][0] * a1[0] + t[0][1] * a1[1] + t[0][2] * a1[2],
        t[1][0] * a1[0] + t[1][1] * a1[1] + t[1][2] * a1[2],
        t[2][0] * a1[0] + t[2][1] * a1[1] + t[2][2] * a1[2],
    ];
    let local = conic_to_ellipse([a1[0], a1[1], a1[2], a2[0], a2[1], a2[2]])?;
    let ellipse = Ellipse2 {
        center: frame.to_world(local.center),
        semi_major: local.semi_major * frame.scale,
        semi_minor: local.semi_minor * frame.scale,
        angle: local.angle,
    };
    (all_finite(&[
        ellipse.center.x,
        ellipse.center.y,
        ellipse.semi_major,
        ellipse.semi_minor,
        ellipse.angle,
    ]) && ellipse.semi_minor > 0.0)
        .then_some(ellipse)
}

/// Refines an ellipse to minimise the sum of squared *geometric* (Euclidean) distances
/// to `points`, starting from `initial` (typically [`fit_ellipse`]'s algebraic fit).
///
/// The algebraic fit is exact on noise-free points but, with noise, biased towards
/// smaller and rounder ellipses on partial arcs; this removes most of that bias.
/// Method: Levenberg–Marquardt over `(centre, a, b, angle)`. The residual of point `pᵢ`
/// is its signed distance `dᵢ = nᵢ·(pᵢ − x(θᵢ))` to its closest point `x(θᵢ)`
/// ([`Ellipse2::closest_point`]) with outward unit normal `nᵢ`; since `θᵢ` minimises the
/// distance, `∂dᵢ/∂q = −nᵢ·∂x(θᵢ)/∂q` with `θᵢ` held fixed, where
/// `∂x/∂centre = I`, `∂x/∂a = cos θ·u`, `∂x/∂b = sin θ·v` and
/// `∂x/∂angle = a·cos θ·v − b·sin θ·u`. At most 30 iterations; a step is taken only if it
/// lowers the cost and keeps both semi-axes positive, so the result is never worse
/// than `initial`.
///
/// Returns `initial` unchanged when there are fewer than five points, a point is not
/// finite, or `initial` is not a proper ellipse (non-finite values or a semi-axis ≤ 0).
/// The result satisfies `semi_major ≥ semi_minor > 0` and `angle ∈ (−π/2, π/2]`. On
/// points along a nearly straight line the geometric optimum is an ever larger, flatter
/// ellipse, and the refinement follows it for its 30 iterations: check the size against
/// the extent of the points.
pub fn refine_ellipse(initial: &Ellipse2, points: &[DVec2]) -> Ellipse2 {
    refine_ellipse_within(initial, points, 0.0)
}

/// [`refine_ellipse`], stopping as soon as a step improves the RMS distance by at most
/// `tolerance` times the points' spread (their largest distance from their centroid).
///
/// Where the points determine the ellipse poorly (a short or shallow arc, which many
/// ellipses fit almost equally well) the refinement otherwise creeps along a valley of
/// nearly equal costs for all of its 30 iterations, each of which finds the closest
/// point of every point, for an improvement of a fraction of a pixel; a tolerance of
/// `1e-5` (0.01 px on a stroke 1,000 px across) stops it there. A tolerance of 0 (or
/// less, or NaN) is [`refine_ellipse`] itself: it stops only when a step lowers the cost
/// by less than rounding.
///
/// # Examples
///
/// ```
/// use geosnap_core::geom::{fit_ellipse, refine_ellipse_within};
/// use glam::DVec2;
///
/// // A third of a circle of radius 100, slightly bent out of shape.
/// let points: Vec<DVec2> = (0..40)
///     .map(|i| {
///         let t = 2.1 * f64::from(i) / 39.0;
///         (100.0 + (5.0 * t).sin()) * DVec2::from_angle(t)
///     })
///     .collect();
/// let start = fit_ellipse(&points).unwrap();
/// let refined = refine_ellipse_within(&start, &points, 1e-5);
/// assert!(refined.rms_distance(&points) <= start.rms_distance(&points));
/// ```
pub fn refine_ellipse_within(initial: &Ellipse2, points: &[DVec2], tolerance: f64) -> Ellipse2 {
    let proper = all_finite(&[
        initial.center.x,
        initial.center.y,
        initial.semi_major,
        initial.semi_minor,
        initial.angle,
    ]) && initial.semi_major > 0.0
        && initial.semi_minor > 0.0;
    if points.len() < 5 || !proper {
        return *initial;
    }
    let Some(frame) = Frame::new(points) else {
        return *initial;
    };
    let local: Vec<DVec2> = points.iter().map(|&p| frame.to_local(p)).collect();
    let to_params = |e: &Ellipse2| -> [f64; 5] {
        let c = frame.to_local(e.center);
        [
            c.x,
            c.y,
            e.semi_major / frame.scale,
            e.semi_minor / frame.scale,
            e.angle,
        ]
    };
    let to_ellipse = |q: &[f64; 5]| Ellipse2 {
        center: DVec2::new(q[0], q[1]),
        semi_major: q[2],
        semi_minor: q[3],
        angle: q[4],
    };
    // The closest points of the current ellipse serve both its cost and the next normal
    // equations; a trial's are kept when the step is taken.
    let mut feet = Vec::with_capacity(local.len());
    let mut trial_feet = Vec::with_capacity(local.len());
    let mut q = to_params(initial);
    let mut cost = feet_of(&to_ellipse(&q), &local, &mut feet);
    if !cost.is_finite() {
        return *initial;
    }
    let mut damping = 1e-3;
    let rms = |cost: f64| (cost / local.len() as f64).sqrt();
    for _ in 0..30 {
        let equations = geometric_normal_equations(&to_ellipse(&q), &local, &feet);
        let cost_of = |trial: &[f64; 5]| feet_of(&to_ellipse(trial), &local, &mut trial_feet);
        let before = cost;
        let (taken, more) = damped_step(equations, &mut q, &mut cost, &mut damping, cost_of);
        if taken {
            std::mem::swap(&mut feet, &mut trial_feet);
        }
        // The local frame's unit is the points' spread.
        if !more || (tolerance > 0.0 && rms(before) - rms(cost) <= tolerance) {
            break;
        }
    }
    let refined = normalise_axes(Ellipse2 {
        center: frame.to_world(DVec2::new(q[0], q[1])),
        semi_major: q[2] * frame.scale,
        semi_minor: q[3] * frame.scale,
        angle: q[4],
    });
    let ok = all_finite(&[
        refined.center.x,
        refined.center.y,
        refined.semi_major,
        refined.semi_minor,
        refined.angle,
    ]) && refined.semi_minor > 0.0;
    if ok {
        refined
    } else {
        *initial
    }
}

/// One Levenberg–Marquardt step of [`refine_ellipse`] from the normal `equations` at
/// `q`: the damping grows until a step lowers `cost` (at most ten tries), then shrinks.
/// Updates `q`, `cost` and `damping`. Returns whether a step was taken (the last call of
/// `cost_of` was at the new `q`) and whether to go on: the step lowered the cost by
/// more than rounding.
fn damped_step(
    (jtj, jtr): ([[f64; 5]; 5], [f64; 5]),
    q: &mut [f64; 5],
    cost: &mut f64,
    damping: &mut f64,
    mut cost_of: impl FnMut(&[f64; 5]) -> f64,
) -> (bool, bool) {
    for _ in 0..10 {
        let mut damped = jtj;
        for (i, row) in damped.iter_mut().enumerate() {
            row[i] += *damping * (jtj[i][i] + 1e-12);
        }
        let Some(delta) = solve_n(damped, jtr) else {
            *damping *= 10.0;
            continue;
        };
        let trial: [f64; 5] = std::array::from_fn(|i| q[i] + delta[i]);
        let trial_cost = if trial[2] > 0.0 && trial[3] > 0.0 {
            cost_of(&trial)
        } else {
            f64::INFINITY
        };
        if trial_cost < *cost {
            let decrease = *cost - trial_cost;
            *q = trial;
            *cost = trial_cost;
            *damping = (*damping / 3.0).max(1e-12);
            return (true, decrease > 1e-10 * cost.max(1e-300));
        }
        *damping *= 4.0;
    }
    (false, false)
}

/// The sum of squared distances from `points` to `e`, filling `feet` with their closest
/// points ([`Ellipse2::closest_point`]).
fn feet_of(e: &Ellipse2, points: &[DVec2], feet: &mut Vec<Foot>) -> f64 {
    let u = e.major_axis();
    feet.clear();
    feet.extend(points.iter().map(|&p| e.foot(u, p)));
    points
        .iter()
        .zip(feet.iter())
        .map(|(&p, foot)| p.distance(foot.point).powi(2))
        .sum()
}

/// The Gauss–Newton normal equations `(JᵀJ, −Jᵀd)` of the signed geometric distances
/// of `points` to `e` with respect to `(centre x, centre y, a, b, angle)`, given their
/// closest points `feet` ([`feet_of`]); see [`refine_ellipse`].
fn geometric_normal_equations(
    e: &Ellipse2,
    points: &[DVec2],
    feet: &[Foot],
) -> ([[f64; 5]; 5], [f64; 5]) {
    let (u, v) = (e.major_axis(), e.minor_axis());
    let mut jtj = [[0.0; 5]; 5];
    let mut jtr = [0.0; 5];
    for (&p, foot) in points.iter().zip(feet) {
        let (s, c, x) = (foot.sin, foot.cos, foot.point);
        // The outward normal is the gradient of (x_u/a)² + (x_v/b)², ∝ (b·cos θ, a·sin θ).
        let normal = (e.semi_minor * c * u + e.semi_major * s * v).normalize_or_zero();
        let d = normal.dot(p - x);
        let row = [
            -normal.x,
            -normal.y,
            -c * normal.dot(u),
            -s * normal.dot(v),
            -normal.dot(e.semi_major * c * v - e.semi_minor * s * u),
        ];
        for (i, &ri) in row.iter().enumerate() {
            jtr[i] -= ri * d;
            for (j, &rj) in row.iter().enumerate() {
                jtj[i][j] += ri * rj;
            }
        }
    }
    (jtj, jtr)
}

/// Orders the semi-axes (major ≥ minor) and folds the angle into `(−π/2, π/2]`.
fn normalise_axes(e: Ellipse2) -> Ellipse2 {
    let (semi_major, semi_minor, angle) = if e.semi_major >= e.semi_minor {
        (e.semi_major, e.semi_minor, e.angle)
    } else {
        (e.semi_minor, e.semi_major, e.angle + FRAC_PI_2)
    };
    // An axis is a line, not a direction.
    let mut angle = wrap_angle(angle);
    if angle > FRAC_PI_2 {
        angle -= PI;
    } else if angle <= -FRAC_PI_2 {
        angle += PI;
    }
    Ellipse2 {
        center: e.center,
        semi_major,
        semi_minor,
        angle,
    }
}

/// The normalised frame of a point set: `local = (p − origin) / scale` with the origin at
/// the centroid and the largest local distance 1.
struct Frame {
    origin: DVec2,
    scale: f64,
}

impl Frame {
    /// `None` for no points, a non-finite point, coincident points, or a spread that
    /// overflows or underflows.
    fn new(points: &[DVec2]) -> Option<Self> {
        if points.is_empty() || !points.iter().all(|p| p.is_finite()) {
            return None;
        }
        let n = points.len() as f64;
        // Dividing before summing keeps the sum finite for coordinates near f64::MAX.
        let origin = points.iter().map(|&p| p / n).sum::<DVec2>();
        let scale = points
            .iter()
            .map(|&p| (p - origin).length())
            .fold(0.0, f64::max);
        (origin.is_finite() && scale.is_finite() && scale >= f64::MIN_POSITIVE)
            .then_some(Self { origin, scale })
    }

    fn to_local(&self, p: DVec2) -> DVec2 {
        (p - self.origin) / self.scale
    }

    fn to_world(&self, q: DVec2) -> DVec2 {
        self.origin + q * self.scale
    }
}

fn all_finite(values: &[f64]) -> bool {
    values.iter().all(|v| v.is_finite())
}

/// Wraps an angle into `(−π, π]`.
fn wrap_angle(theta: f64) -> f64 {
    let mut t = theta % TAU;
    if t > PI {
        t -= TAU;
    } else if t <= -PI {
        t += TAU;
    }
    t
}

/// Solves the 3×3 system `a·x = b`; see [`solve_n`].
fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    solve_n(a, b)
}

/// Solves the N×N system `a·x = b` by Gaussian elimination with partial pivoting.
/// `None` when a pivot is below `1e−13` times the largest entry (numerically singular).
fn solve_n<const N: usize>(mut a: [[f64; N]; N], mut b: [f64; N]) -> Option<[f64; N]> {
    let norm = a.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
    if !(norm > 0.0) || !norm.is_finite() {
        return None;
    }
    for col in 0..N {
        let pivot = (col..N).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if !(a[pivot][col].abs() > 1e-13 * norm) {
            return None;
        }
        a.swap(col, pivot);
        b.swap(col, pivot);
        for row in (col + 1)..N {
            let factor = a[row][col] / a[col][col];
            let pivot_row = a[col];
            for (k, value) in a[row].iter_mut().enumerate().skip(col) {
                *value -= factor * pivot_row[k];
            }
            b[row] -= factor * b[col];
        }
    }
    let mut x = [0.0; N];
    for row in (0..N).rev() {
        let tail: f64 = ((row + 1)..N).map(|k| a[row][k] * x[k]).sum();
        x[row] = (b[row] - tail) / a[row][row];
    }
    all_finite(&x).then_some(x)
}

/// The eigenvector of `M·a = λ·C₁·a` that satisfies the ellipse constraint
/// `4·a₀·a₂ − a₁² > 0` (see [`fit_ellipse`]).
fn ellipse_eigenvector(m: &[[f64; 3]; 3]) -> Option<[f64; 3]> {
    let [[m00, m01, m02], [_, m11, m12], [_, _, m22]] = *m;
    // det(M − λC₁) = −4λ³ + c2·λ² + c1·λ + c0, expanded by hand from
    // M − λC₁ = [m00, m01, m02 − 2λ; m01, m11 + λ, m12; m02 − 2λ, m12, m22].
    let c2 = 4.0 * (m02 - m11);
    let c1 = m00 * m22 - 4.0 * m01 * m12 - m02 * m02 + 4.0 * m11 * m02;
    let c0 = m00 * m11 * m22 - m00 * m12 * m12 - m01 * m01 * m22 + 2.0 * m01 * m12 * m02
        - m11 * m02 * m02;
    let cubic = |l: f64| ((-4.0 * l + c2) * l + c1) * l + c0;
    let dcubic = |l: f64| (-12.0 * l + 2.0 * c2) * l + c1;
    let mut best: Option<([f64; 3], f64)> = None;
    for root in real_cubic_roots(-c2 / 4.0, -c1 / 4.0, -c0 / 4.0) {
        let mut l = root;
        for _ in 0..3 {
            let d = dcubic(l);
            if d == 0.0 {
                break;
            }
            let next = l - cubic(l) / d;
            if !next.is_finite() || cubic(next).abs() >= cubic(l).abs() {
                break;
            }
            l = next;
        }
        let rows = [
            [m00, m01, m02 - 2.0 * l],
            [m01, m11 + l, m12],
            [m02 - 2.0 * l, m12, m22],
        ];
        let Some(v) = null_vector(&rows) else {
            continue;
        };
        let constraint = 4.0 * v[0] * v[2] - v[1] * v[1];
        if !(constraint > 0.0) {
            continue;
        }
        let mv = [
            m00 * v[0] + m01 * v[1] + m02 * v[2],
            m01 * v[0] + m11 * v[1] + m12 * v[2],
            m02 * v[0] + m12 * v[1] + m22 * v[2],
        ];
        let rayleigh = (v[0] * mv[0] + v[1] * mv[1] + v[2] * mv[2]) / constraint;
        if best.is_none_or(|(_, r)| rayleigh < r) {
            best = Some((v, rayleigh));
        }
    }
    best.map(|(v, _)| v)
}

/// The real roots of the monic cubic `x³ + p2·x² + p1·x + p0`. The generalised
/// eigenvalues of a symmetric positive semi-definite pencil are real, so the
/// trigonometric method applies; rounding that pushes the discriminant the wrong way is
/// absorbed by clamping, and a genuinely single real root is found by Cardano's formula.
fn real_cubic_roots(p2: f64, p1: f64, p0: f64) -> Vec<f64> {
    // Depressed cubic t³ + p·t + q with x = t − p2/3.
    let shift = p2 / 3.0;
    let p = p1 - p2 * p2 / 3.0;
    let q = 2.0 * p2 * p2 * p2 / 27.0 - p2 * p1 / 3.0 + p0;
    let disc = (q / 2.0).powi(2) + (p / 3.0).powi(3);
    let scale = (q / 2.0).powi(2).max((p / 3.0).abs().powi(3));
    if p < 0.0 && disc <= 1e-12 * scale {
        let r = 2.0 * (-p / 3.0).sqrt();
        let arg = (3.0 * q / (p * r)).clamp(-1.0, 1.0);
        let phi = arg.acos() / 3.0;
        (0..3)
            .map(|k| r * (phi - TAU * f64::from(k) / 3.0).cos() - shift)
            .collect()
    } else {
        let s = disc.max(0.0).sqrt();
        vec![(-q / 2.0 + s).cbrt() + (-q / 2.0 - s).cbrt() - shift]
    }
}

/// A unit null vector of a (numerically) rank-2 3×3 matrix: the longest cross product of
/// two of its rows. `None` when every cross product vanishes (rank ≤ 1).
fn null_vector(rows: &[[f64; 3]; 3]) -> Option<[f64; 3]> {
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let candidates = [
        cross(rows[0], rows[1]),
        cross(rows[0], rows[2]),
        cross(rows[1], rows[2]),
    ];
    let norm = |v: &[f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let best = candidates
        .into_iter()
        .max_by(|x, y| norm(x).total_cmp(&norm(y)))?;
    let len = norm(&best);
    (len > 0.0 && len.is_finite()).then(|| [best[0] / len, best[1] / len, best[2] / len])
}

/// Converts the conic `a·x² + b·xy + c·y² + d·x + e·y + f = 0` to a parametric ellipse.
///
/// The centre solves `∇F = 0`: `x₀ = (b·e − 2c·d)/(4ac − b²)`,
/// `y₀ = (b·d − 2a·e)/(4ac − b²)`. Translated there the conic reads `qᵀAq + F₀ = 0` with
/// `A = [a b/2; b/2 c]` and `F₀ = F(x₀, y₀) = f + (d·x₀ + e·y₀)/2`. `A` has eigenvalues
/// `(a + c)/2 ± √(((a − c)/2)² + (b/2)²)`, the larger one along the angle
/// `½·atan2(b, a − c)`, and the semi-axis along the eigenvector of `λ` is `√(−F₀/λ)`;
/// the smaller `|λ|` gives the major axis. `None` unless `4ac − b² > 0` and both
/// `−F₀/λ > 0` (otherwise the conic is a hyperbola, a parabola, or an imaginary or
/// point ellipse).
fn conic_to_ellipse([a, b, c, d, e, f]: [f64; 6]) -> Option<Ellipse2> {
    let denom = 4.0 * a * c - b * b;
    if !(denom > 0.0) {
        return None;
    }
    let center = DVec2::new((b * e - 2.0 * c * d) / denom, (b * d - 2.0 * a * e) / denom);
    let f0 = f + 0.5 * (d * center.x + e * center.y);
    let mean = 0.5 * (a + c);
    let radius = f64::hypot(0.5 * (a - c), 0.5 * b);
    let (l1, l2) = (mean + radius, mean - radius);
    let phi1 = 0.5 * f64::atan2(b, a - c);
    let (ax1, ax2) = (-f0 / l1, -f0 / l2);
    if !(ax1 > 0.0 && ax2 > 0.0) {
        return None;
    }
    Some(normalise_axes(Ellipse2 {
        center,
        semi_major: ax1.sqrt(),
        semi_minor: ax2.sqrt(),
        angle: phi1,
    }))
}

/// The parameter `θ ∈ (−π, π]` of the point of the ellipse `(a·cos θ, b·sin θ)`,
/// `a ≥ b ≥ 0`, closest to `(x, y)`; see [`Ellipse2::closest_point`].
fn closest_theta(a: f64, b: f64, x: f64, y: f64) -> f64 {
    if !(a > 0.0) || !a.is_finite() {
        // A point ellipse (or a broken one): every direction is as good.
        return if x == 0.0 && y == 0.0 {
            0.0
        } else {
            y.atan2(x)
        };
    }
    // Work in units of the semi-major axis, in the first quadrant.
    let (px, py, b) = ((x / a).abs(), (y / a).abs(), b / a);
    let theta = if b <= 1e-12 {
        // A segment from (−1, 0) to (1, 0): the closest point is (clamp(x), 0).
        px.min(1.0).acos()
    } else {
        first_quadrant_theta(b, px, py)
    };
    // Undo the reflection into the first quadrant.
    let theta = if x < 0.0 { PI - theta } else { theta };
    if y < 0.0 {
        -theta
    } else {
        theta
    }
}

/// The closest-point parameter in `[0, π/2]` on `(cos θ, b·sin θ)`, `0 < b ≤ 1`, for a
/// point with `px, py ≥ 0`.
fn first_quadrant_theta(b: f64, px: f64, py: f64) -> f64 {
    let e2 = 1.0 - b * b;
    let dist2 = |t: f64| {
        let (s, c) = t.sin_cos();
        (px - c).powi(2) + (py - b * s).powi(2)
    };
    // f(θ) = (1 − b²)·sin θ·cos θ − x·sin θ + y·b·cos θ and its derivative.
    let f_df = |t: f64| {
        let (s, c) = t.sin_cos();
        (
            e2 * s * c - px * s + py * b * c,
            e2 * (c * c - s * s) - px * c - py * b * s,
        )
    };
    // Initial guess: the evolute iteration. The centre of curvature of the point
    // (tx, b·ty) is (e2·tx³, −e2·ty³/b); moving along the ray from it towards the query
    // point by the radius of curvature gives the next estimate.
    let (mut tx, mut ty) = (
        std::f64::consts::FRAC_1_SQRT_2,
        std::f64::consts::FRAC_1_SQRT_2,
    );
    for _ in 0..3 {
        let (ex, ey) = (e2 * tx.powi(3), -e2 * ty.powi(3) / b);
        let (rx, ry) = (tx - ex, b * ty - ey);
        let (qx, qy) = (px - ex, py - ey);
        // Plain square roots: the values are bounded by 1/b ≤ 1e12, far from overflow.
        let (r, q) = ((rx * rx + ry * ry).sqrt(), (qx * qx + qy * qy).sqrt());
        if !(q > 0.0 && r.is_finite() && q.is_finite()) {
            break;
        }
        let nx = ((qx * r / q + ex) / 1.0).clamp(0.0, 1.0);
        let ny = ((qy * r / q + ey) / b).clamp(0.0, 1.0);
        let len = (nx * nx + ny * ny).sqrt();
        if !(len > 0.0) || !len.is_finite() {
            break;
        }
        (tx, ty) = (nx / len, ny / len);
    }
    let mut theta = ty.atan2(tx).clamp(0.0, FRAC_PI_2);
    // Safeguarded Newton on f in the bracket [lo, hi] where f(lo) ≥ 0 ≥ f(hi).
    let (mut lo, mut hi) = (0.0, FRAC_PI_2);
    for _ in 0..60 {
        let (value, slope) = f_df(theta);
        if value > 0.0 {
            lo = theta;
        } else if value < 0.0 {
            hi = theta;
        } else {
            break;
        }
        let newton = theta - value / slope;
        let next = if newton.is_finite() && newton >= lo && newton <= hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        let step = (next - theta).abs();
        theta = next;
        if step <= 4.0 * f64::EPSILON || hi - lo <= 4.0 * f64::EPSILON {
            break;
        }
    }
    // f can have three roots in the quadrant (points inside the evolute); the vertices
    // are candidates too, and the nearest candidate wins.
    let (vertex_x, vertex_y) = ((px - 1.0).powi(2) + py * py, px * px + (py - b).powi(2));
    let mut best = (theta, dist2(theta));
    for candidate in [(0.0, vertex_x), (FRAC_PI_2, vertex_y)] {
        if candidate.1 < best.1 {
            best = candidate;
        }
    }
    best.0
}

#[cfg(test)]
mod tests {
    use std::f64::consts::{FRAC_PI_2, PI, TAU};

    use glam::DVec2;
    use proptest::prelude::*;

    use super::{fit_circle, fit_ellipse, fit_line, refine_ellipse, Ellipse2};

    /// Deterministic pseudo-random numbers in [−1, 1] (xorshift), so tests need no crate.
    struct Noise(u64);

    impl Noise {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    fn ellipse_points(e: &Ellipse2, from: f64, to: f64, n: usize) -> Vec<DVec2> {
        (0..n)
            .map(|i| e.point_at(from + (to - from) * i as f64 / (n - 1) as f64))
            .collect()
    }

    /// The angle between two axes (lines), in [0, π/2].
    fn axis_angle_diff(a: f64, b: f64) -> f64 {
        let d = (a - b).rem_euclid(PI);
        d.min(PI - d)
    }

    fn assert_ellipse_close(got: &Ellipse2, want: &Ellipse2, tol: f64) {
        let size = want.semi_major;
        assert!(
            got.center.distance(want.center) < tol * size,
            "centre {got:?} vs {want:?}"
        );
        assert!(
            (got.semi_major - want.semi_major).abs() < tol * size,
            "major {got:?} vs {want:?}"
        );
        assert!(
            (got.semi_minor - want.semi_minor).abs() < tol * size,
            "minor {got:?} vs {want:?}"
        );
        if want.semi_major - want.semi_minor > 0.05 * size {
            assert!(
                axis_angle_diff(got.angle, want.angle) < tol * 10.0,
                "angle {got:?} vs {want:?}"
            );
        }
    }

    #[test]
    fn line_recovers_exact_segment() {
        let a = DVec2::new(3.0, -2.0);
        let dir = DVec2::new(4.0, 3.0) / 5.0;
        let points: Vec<DVec2> = (0..11).map(|i| a + dir * i as f64).collect();
        let line = fit_line(&points).unwrap();
        assert!(line.direction.distance(dir) < 1e-12, "{line:?}");
        assert!(line.rms_residual < 1e-12, "{line:?}");
        assert!((line.length() - 10.0).abs() < 1e-12, "{line:?}");
        assert!(line.start().distance(a) < 1e-12, "{line:?}");
        assert!(line.end().distance(a + 10.0 * dir) < 1e-12, "{line:?}");
        assert!(
            (line.distance(a + 2.0 * dir.perp()) - 2.0).abs() < 1e-12,
            "{line:?}"
        );
        // Reversed order reverses the direction.
        let reversed: Vec<DVec2> = points.iter().rev().copied().collect();
        let back = fit_line(&reversed).unwrap();
        assert!(back.direction.distance(-dir) < 1e-12, "{back:?}");
    }

    #[test]
    fn line_residual_is_rms_perpendicular_distance() {
        // Points alternately ±0.5 off the x axis.
        let points: Vec<DVec2> = (0..20)
            .map(|i| DVec2::new(i as f64, if i % 2 == 0 { 0.5 } else { -0.5 }))
            .collect();
        let line = fit_line(&points).unwrap();
        assert!((line.rms_residual - 0.5).abs() < 0.01, "{line:?}");
        assert!(line.direction.x.abs() > 0.999, "{line:?}");
    }

    #[test]
    fn line_degenerate_inputs() {
        assert!(fit_line(&[]).is_none());
        assert!(fit_line(&[DVec2::ONE]).is_none());
        assert!(fit_line(&[DVec2::ONE, DVec2::ONE, DVec2::ONE]).is_none());
        assert!(fit_line(&[DVec2::ONE, DVec2::new(f64::NAN, 0.0)]).is_none());
        assert!(fit_line(&[DVec2::ZERO, DVec2::X]).is_some());
    }

    #[test]
    fn circle_recovers_exact_and_partial_arcs() {
        let center = DVec2::new(120.0, -40.0);
        for (from, to) in [(0.0, TAU), (0.3, 0.3 + PI), (1.0, 1.0 + FRAC_PI_2)] {
            let points: Vec<DVec2> = (0..30)
                .map(|i| center + 7.5 * DVec2::from_angle(from + (to - from) * f64::from(i) / 29.0))
                .collect();
            let circle = fit_circle(&points).unwrap();
            assert!(circle.center.distance(center) < 1e-9, "{circle:?}");
            assert!((circle.radius - 7.5).abs() < 1e-9, "{circle:?}");
            assert!(circle.rms_residual < 1e-9, "{circle:?}");
        }
    }

    #[test]
    fn circle_with_noise_and_degenerate_inputs() {
        let mut noise = Noise(7);
        let points: Vec<DVec2> = (0..200)
            .map(|i| {
                let t = PI * f64::from(i) / 199.0;
                DVec2::from_angle(t) * (50.0 + 0.5 * noise.next())
            })
            .collect();
        let circle = fit_circle(&points).unwrap();
        assert!(circle.center.length() < 0.5, "{circle:?}");
        assert!((circle.radius - 50.0).abs() < 0.5, "{circle:?}");
        assert!(circle.rms_residual < 0.5, "{circle:?}");
        let p = circle.point_at(0.7);
        assert!(circle.distance(p) < 1e-9, "{circle:?}");
        assert!(fit_circle(&[DVec2::ZERO, DVec2::X]).is_none());
        let collinear: Vec<DVec2> = (0..10).map(|i| DVec2::splat(f64::from(i))).collect();
        assert!(fit_circle(&collinear).is_none());
    }

    #[test]
    fn ellipse_recovers_exact_full_and_partial_arcs() {
        let truth = Ellipse2 {
            center: DVec2::new(1500.0, 2400.0),
            semi_major: 300.0,
            semi_minor: 90.0,
            angle: 0.4,
        };
        for (from, to, n) in [
            (0.0, TAU, 60),
            (0.2, 0.2 + PI, 40),
            (-1.0, -1.0 + FRAC_PI_2, 30),
            (2.0, 2.0 + FRAC_PI_2, 30),
        ] {
            let points = ellipse_points(&truth, from, to, n);
            let fit = fit_ellipse(&points).unwrap();
            assert_ellipse_close(&fit, &truth, 1e-9);
            assert!(fit.rms_distance(&points) < 1e-9, "{fit:?}");
        }
    }

    #[test]
    fn ellipse_recovers_circles_and_axis_aligned_ellipses() {
        for truth in [
            Ellipse2 {
                center: DVec2::new(-3.0, 4.0),
                semi_major: 2.0,
                semi_minor: 2.0,
                angle: 0.0,
            },
            Ellipse2 {
                center: DVec2::ZERO,
                semi_major: 5.0,
                semi_minor: 1.0,
                angle: FRAC_PI_2,
            },
            Ellipse2 {
                center: DVec2::new(1e6, -1e6),
                semi_major: 10.0,
                semi_minor: 0.5,
                angle: -0.3,
            },
        ] {
            let points = ellipse_points(&truth, 0.0, TAU, 50);
            let fit = fit_ellipse(&points).unwrap();
            assert_ellipse_close(&fit, &truth, 1e-9);
            assert!(fit.semi_major >= fit.semi_minor, "{fit:?}");
            assert!(fit.angle > -FRAC_PI_2 && fit.angle <= FRAC_PI_2, "{fit:?}");
        }
    }

    #[test]
    fn ellipse_with_noise_full_and_partial() {
        let truth = Ellipse2 {
            center: DVec2::new(200.0, 100.0),
            semi_major: 100.0,
            semi_minor: 40.0,
            angle: -0.7,
        };
        let mut noise = Noise(42);
        // Noise up to 1 % of the semi-major axis; (from, to, algebraic tol, refined tol).
        // On a 90° arc the algebraic fit's bias is large (semi-major 47 instead of 100
        // here); the geometric refinement recovers it.
        for (from, to, tol_algebraic, tol_refined) in [
            (0.0, TAU, Some(0.01), 0.01),
            (0.5, 0.5 + PI, Some(0.01), 0.01),
            (2.0, 2.0 + 2.1, Some(0.2), 0.05),
            (-1.0, -1.0 + FRAC_PI_2, None, 0.05),
        ] {
            let points: Vec<DVec2> = ellipse_points(&truth, from, to, 150)
                .into_iter()
                .map(|p| p + DVec2::new(noise.next(), noise.next()))
                .collect();
            let fit = fit_ellipse(&points).unwrap();
            if let Some(tol) = tol_algebraic {
                assert_ellipse_close(&fit, &truth, tol);
            }
            let refined = refine_ellipse(&fit, &points);
            assert_ellipse_close(&refined, &truth, tol_refined);
            let (before, after) = (fit.rms_distance(&points), refined.rms_distance(&points));
            assert!(after <= before && after < 0.7, "{before} {after}");
        }
    }

    #[test]
    fn refinement_keeps_exact_fits_and_rejects_bad_input() {
        let truth = Ellipse2 {
            center: DVec2::new(-5.0, 8.0),
            semi_major: 3.0,
            semi_minor: 1.0,
            angle: 1.2,
        };
        let points = ellipse_points(&truth, 0.0, 3.0, 40);
        let refined = refine_ellipse(&truth, &points);
        assert_ellipse_close(&refined, &truth, 1e-9);
        // A rough start converges to the truth on noise-free points.
        let rough = Ellipse2 {
            center: truth.center + DVec2::new(0.3, -0.2),
            semi_major: 2.5,
            semi_minor: 1.3,
            angle: 1.0,
        };
        assert_ellipse_close(&refine_ellipse(&rough, &points), &truth, 1e-6);
        let bad = Ellipse2 {
            semi_minor: 0.0,
            ..truth
        };
        assert_eq!(refine_ellipse(&bad, &points), bad);
        assert_eq!(refine_ellipse(&truth, &points[..4]), truth);
    }

    #[test]
    fn refinement_within_a_tolerance_stops_early_at_nearly_the_same_cost() {
        // A shallow arc (70°) of a circle with a little wobble: poorly determined, the
        // refinement creeps along a valley of nearly equal costs.
        let points: Vec<DVec2> = (0..64)
            .map(|i| {
                let t = 1.2 * f64::from(i) / 63.0;
                (100.0 + 0.3 * (9.0 * t).sin()) * DVec2::from_angle(t)
            })
            .collect();
        let start = fit_ellipse(&points).unwrap();
        let full = refine_ellipse(&start, &points);
        assert_eq!(super::refine_ellipse_within(&start, &points, 0.0), full);
        let quick = super::refine_ellipse_within(&start, &points, 1e-5);
        let (rms_full, rms_quick) = (full.rms_distance(&points), quick.rms_distance(&points));
        assert!(rms_quick <= start.rms_distance(&points));
        // Within the tolerance of the spread (about 100) per step taken.
        assert!(
            rms_quick - rms_full <= 30.0 * 1e-5 * 100.0,
            "{rms_quick} {rms_full}"
        );
    }

    #[test]
    fn ellipse_degenerate_inputs() {
        assert!(fit_ellipse(&[]).is_none());
        assert!(fit_ellipse(&[DVec2::ZERO, DVec2::X, DVec2::Y, DVec2::ONE]).is_none());
        let collinear: Vec<DVec2> = (0..20)
            .map(|i| DVec2::new(f64::from(i), 2.0 * f64::from(i)))
            .collect();
        assert!(fit_ellipse(&collinear).is_none());
        assert!(fit_ellipse(&[DVec2::ONE; 10]).is_none());
        // Points on a hyperbola still get an ellipse (Fitzgibbon's constraint), or none,
        // but never NaN.
        let hyperbola: Vec<DVec2> = (1..30)
            .map(|i| {
                let t = f64::from(i) / 10.0;
                DVec2::new(t, 1.0 / t)
            })
            .collect();
        if let Some(e) = fit_ellipse(&hyperbola) {
            assert!(e.semi_major.is_finite() && e.semi_minor > 0.0, "{e:?}");
        }
    }

    /// Brute-force distance by dense sampling plus local golden-section refinement.
    fn brute_distance(e: &Ellipse2, p: DVec2) -> f64 {
        let n = 20_000;
        let d = |t: f64| e.point_at(t).distance(p);
        let (mut best_t, mut best) = (0.0, f64::INFINITY);
        for i in 0..n {
            let t = TAU * f64::from(i) / f64::from(n);
            if d(t) < best {
                best = d(t);
                best_t = t;
            }
        }
        let (mut lo, mut hi) = (best_t - TAU / f64::from(n), best_t + TAU / f64::from(n));
        for _ in 0..100 {
            let m1 = lo + (hi - lo) / 3.0;
            let m2 = hi - (hi - lo) / 3.0;
            if d(m1) < d(m2) {
                hi = m2;
            } else {
                lo = m1;
            }
        }
        d(0.5 * (lo + hi)).min(best)
    }

    #[test]
    fn distance_matches_brute_force() {
        let ellipses = [
            Ellipse2 {
                center: DVec2::new(1.0, 2.0),
                semi_major: 5.0,
                semi_minor: 3.0,
                angle: 0.3,
            },
            Ellipse2 {
                center: DVec2::ZERO,
                semi_major: 4.0,
                semi_minor: 4.0,
                angle: 0.0,
            },
            Ellipse2 {
                center: DVec2::ZERO,
                semi_major: 10.0,
                semi_minor: 0.05,
                angle: 1.0,
            },
            Ellipse2 {
                center: DVec2::new(-2.0, 0.0),
                semi_major: 1.0,
                semi_minor: 3.0,
                angle: 0.0,
            },
        ];
        let mut noise = Noise(3);
        for e in &ellipses {
            let size = e.semi_major.max(e.semi_minor);
            for _ in 0..200 {
                let p = e.center + 1.5 * size * DVec2::new(noise.next(), noise.next());
                let got = e.distance(p);
                let want = brute_distance(e, p);
                assert!((got - want).abs() < 1e-9 * size, "{e:?} {p} {got} {want}");
            }
            // Points on the curve, the centre and the axes.
            for t in [0.0, 0.5, 1.0, 2.0, 3.0, -1.0, PI] {
                assert!(e.distance(e.point_at(t)) < 1e-9 * size, "{e:?} {t}");
            }
            for p in [
                e.center,
                e.center + 0.3 * e.semi_major * e.major_axis(),
                e.center + 0.3 * e.semi_minor * e.minor_axis(),
            ] {
                let want = brute_distance(e, p);
                assert!((e.distance(p) - want).abs() < 1e-9 * size, "{e:?} {p}");
            }
        }
    }

    #[test]
    fn closest_point_parameters_and_degenerate_ellipses() {
        let e = Ellipse2 {
            center: DVec2::new(3.0, 1.0),
            semi_major: 4.0,
            semi_minor: 2.0,
            angle: 0.5,
        };
        for t in [-3.0, -1.5, 0.0, 0.8, 2.5, 3.1] {
            let (theta, p) = e.closest_point(e.point_at(t));
            assert!((theta - t).abs() < 1e-9, "{t} {theta}");
            assert!(p.distance(e.point_at(t)) < 1e-9, "{t}");
            // Outside along the normal.
            let tangent = e.major_axis() * (-4.0 * t.sin()) + e.minor_axis() * (2.0 * t.cos());
            let q = e.point_at(t) - 0.5 * tangent.perp().normalize();
            assert!((e.distance(q) - 0.5).abs() < 1e-9, "{t}");
        }
        let segment = Ellipse2 {
            center: DVec2::ZERO,
            semi_major: 2.0,
            semi_minor: 0.0,
            angle: 0.0,
        };
        assert!((segment.distance(DVec2::new(1.0, 3.0)) - 3.0).abs() < 1e-12);
        assert!((segment.distance(DVec2::new(5.0, 0.0)) - 3.0).abs() < 1e-12);
        let point = Ellipse2 {
            semi_major: 0.0,
            ..segment
        };
        assert!((point.distance(DVec2::new(3.0, 4.0)) - 5.0).abs() < 1e-12);
    }

    #[test]
    fn angular_span_of_arcs() {
        let e = Ellipse2 {
            center: DVec2::new(10.0, 10.0),
            semi_major: 5.0,
            semi_minor: 2.0,
            angle: 0.2,
        };
        let full = e.angular_span(&ellipse_points(&e, 0.0, TAU, 100)).unwrap();
        assert!(full.sweep > TAU - 0.1, "{full:?}");
        let arc = e
            .angular_span(&ellipse_points(&e, 2.5, 2.5 + 2.0, 50))
            .unwrap();
        assert!((arc.sweep - 2.0).abs() < 1e-9, "{arc:?}");
        assert!((arc.start - 2.5).abs() < 1e-9, "{arc:?}");
        assert!((arc.end() - 4.5).abs() < 1e-9, "{arc:?}");
        // Across the ±π seam, in reverse drawing order.
        let mut seam = ellipse_points(&e, 3.0, 3.0 + 1.0, 20);
        seam.reverse();
        let span = e.angular_span(&seam).unwrap();
        assert!((span.sweep - 1.0).abs() < 1e-9, "{span:?}");
        assert!((span.start - 3.0).abs() < 1e-9, "{span:?}");
        assert!(e.angular_span(&[]).is_none());
        assert!(e.angular_span(&[e.point_at(1.0)]).unwrap().sweep.abs() < 1e-12);
    }

    fn coordinate() -> impl Strategy<Value = f64> {
        prop_oneof![
            -1e3..1e3_f64,
            -1e-200..1e-200_f64,
            -1e200..1e200_f64,
            (-5i32..5).prop_map(f64::from),
        ]
    }

    fn points() -> impl Strategy<Value = Vec<DVec2>> {
        prop_oneof![
            prop::collection::vec(
                (coordinate(), coordinate()).prop_map(|(x, y)| DVec2::new(x, y)),
                0..40
            ),
            // Duplicates.
            (coordinate(), coordinate(), 0usize..12)
                .prop_map(|(x, y, n)| vec![DVec2::new(x, y); n]),
            // Collinear points.
            (
                coordinate(),
                coordinate(),
                prop::collection::vec(-10.0..10.0_f64, 0..20)
            )
                .prop_map(|(x, y, ts)| ts
                    .iter()
                    .map(|t| DVec2::new(x, y) + *t * DVec2::new(0.6, -0.8))
                    .collect()),
            // Noisy ellipses at random scales.
            (
                0.0..TAU,
                1e-6..1e6_f64,
                0.01..1.0_f64,
                0.0..1.0_f64,
                5usize..30
            )
                .prop_map(|(angle, a, ratio, jitter, n)| {
                    let e = Ellipse2 {
                        center: DVec2::new(a, -a),
                        semi_major: a,
                        semi_minor: a * ratio,
                        angle,
                    };
                    (0..n)
                        .map(|i| {
                            e.point_at(i as f64)
                                * (1.0 + jitter * ((i * 7 % 5) as f64 - 2.0) / 20.0)
                        })
                        .collect()
                }),
        ]
    }

    proptest! {
        #[test]
        fn fits_never_panic_or_return_nan(points in points()) {
            if let Some(l) = fit_line(&points) {
                prop_assert!(l.centroid.is_finite() && l.direction.is_finite());
                prop_assert!(l.t_min.is_finite() && l.t_max.is_finite() && l.rms_residual.is_finite());
                prop_assert!((l.direction.length() - 1.0).abs() < 1e-9);
            }
            if let Some(c) = fit_circle(&points) {
                prop_assert!(c.center.is_finite() && c.radius.is_finite() && c.rms_residual.is_finite());
                prop_assert!(c.radius > 0.0);
            }
            if let Some(e) = fit_ellipse(&points) {
                prop_assert!(e.center.is_finite() && e.semi_major.is_finite() && e.angle.is_finite());
                prop_assert!(e.semi_major >= e.semi_minor && e.semi_minor > 0.0);
                let d = e.rms_distance(&points);
                prop_assert!(!d.is_nan());
                let r = refine_ellipse(&e, &points);
                prop_assert!(r.center.is_finite() && r.semi_major.is_finite() && r.angle.is_finite());
                prop_assert!(r.semi_major >= r.semi_minor && r.semi_minor > 0.0);
                if let Some(span) = e.angular_span(&points) {
                    prop_assert!(span.sweep.is_finite() && span.start.is_finite());
                }
            }
        }

        #[test]
        fn distance_is_finite_and_not_above_vertex_distances(
            a in 1e-3..1e3_f64, ratio in 0.0..1.0_f64, angle in -PI..PI,
            x in -2e3..2e3_f64, y in -2e3..2e3_f64,
        ) {
            let e = Ellipse2 { center: DVec2::new(1.0, -2.0), semi_major: a, semi_minor: a * ratio, angle };
            let p = DVec2::new(x, y);
            let d = e.distance(p);
            prop_assert!(d.is_finite() && d >= 0.0);
            for t in [0.0, FRAC_PI_2, PI, -FRAC_PI_2] {
                prop_assert!(d <= e.point_at(t).distance(p) + 1e-9 * (a + p.length()));
            }
            // The distance is at least the gap between |p − c| and the extreme radii.
            let r = (p - e.center).length();
            prop_assert!(d + 1e-9 * (a + r) >= (r - a).max(e.semi_minor - r).max(0.0));
        }
    }
}
