//! Planar spatial algebra (Featherstone, *Rigid Body Dynamics Algorithms* (RBDA), ch. 2, the
//! planar 3-vectors; spatial_v2's `crm`, `plnr` for 3-vectors): motion vectors `(ω, v_x, v_y)`,
//! force vectors `(τ, f_x, f_y)`, coordinate transforms and symmetric 3 × 3 inertias.
//!
//! A vector is expressed in a frame: `v` is the velocity of the body-fixed point at the frame's
//! origin, `τ` the moment about that origin. The articulated-body algorithm puts each body's
//! frame at its centre of mass with the world's axes, so transforms are translations and a
//! body's inertia is `diag(I_c, m, m)` whatever its orientation.

use crate::Scalar;

/// A planar motion vector `(ω, v_x, v_y)` (velocity or acceleration).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Motion<S> {
    /// Angular component `ω`.
    pub angular: S,
    /// Linear component along the frame's x axis.
    pub x: S,
    /// Linear component along the frame's y axis.
    pub y: S,
}

/// A planar force vector `(τ, f_x, f_y)`: moment about the frame's origin and force.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Force<S> {
    /// Moment `τ` about the frame's origin.
    pub torque: S,
    /// Force along the frame's x axis.
    pub x: S,
    /// Force along the frame's y axis.
    pub y: S,
}

/// A symmetric 3 × 3 spatial inertia (motion → force), rows and columns `(angular, x, y)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Inertia<S> {
    pub aa: S,
    pub ax: S,
    pub ay: S,
    pub xx: S,
    pub xy: S,
    pub yy: S,
}

/// The spatial inertia of a rigid body (or a rigidly locked subtree) in compact form: mass `m`,
/// first moment `h = m c` of its centre of mass `c` about the frame's origin, and moment of
/// inertia `I_O` about the origin; as a matrix `[[I_O, −h_y, h_x], [−h_y, m, 0], [h_x, 0, m]]`
/// (RBDA ch. 2, planar rigid-body inertia).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RigidInertia<S> {
    pub mass: S,
    pub hx: S,
    pub hy: S,
    pub about_origin: S,
}

/// The coordinate transform `child_from_parent` (RBDA's `ⁱX_λ(i)`) between two frames with the
/// same (world) axes: the child frame's origin is at `(x, y)` from the parent frame's origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Translation<S> {
    pub x: S,
    pub y: S,
}

impl<S: Scalar> Motion<S> {
    pub(crate) fn zero() -> Self {
        Self { angular: S::zero(), x: S::zero(), y: S::zero() }
    }

    /// `self · c`.
    #[inline(always)]
    pub(crate) fn scale(self, c: S) -> Self {
        Self { angular: self.angular * c, x: self.x * c, y: self.y * c }
    }

    /// `self × m` (RBDA's `crm`, planar: `(0, v_y m_ω − ω m_y, ω m_x − v_x m_ω)`).
    #[inline(always)]
    pub(crate) fn cross_motion(self, m: Motion<S>) -> Motion<S> {
        Motion {
            angular: S::zero(),
            x: self.y * m.angular - self.angular * m.y,
            y: self.angular * m.x - self.x * m.angular,
        }
    }

    /// `self + other`.
    #[inline(always)]
    pub(crate) fn add(self, other: Motion<S>) -> Self {
        Self { angular: self.angular + other.angular, x: self.x + other.x, y: self.y + other.y }
    }
}

impl<S: Scalar> Force<S> {
    pub(crate) fn zero() -> Self {
        Self { torque: S::zero(), x: S::zero(), y: S::zero() }
    }

    /// The power `fᵀ m` of this force on a motion `m`.
    #[inline(always)]
    pub(crate) fn dot(self, m: Motion<S>) -> S {
        self.torque * m.angular + self.x * m.x + self.y * m.y
    }

    /// `self + other`.
    #[inline(always)]
    pub(crate) fn add(self, other: Force<S>) -> Self {
        Self { torque: self.torque + other.torque, x: self.x + other.x, y: self.y + other.y }
    }

    /// `self · c`.
    #[inline(always)]
    pub(crate) fn scale(self, c: S) -> Self {
        Self { torque: self.torque * c, x: self.x * c, y: self.y * c }
    }
}

impl<S: Scalar> Inertia<S> {
    pub(crate) fn zero() -> Self {
        let z = S::zero();
        Self { aa: z, ax: z, ay: z, xx: z, xy: z, yy: z }
    }

    /// A body's inertia in its centre-of-mass frame: `diag(I_c, m, m)`.
    pub(crate) fn body(mass: f64, inertia: f64) -> Self {
        let z = S::zero();
        Self { aa: S::from(inertia), ax: z, ay: z, xx: S::from(mass), xy: z, yy: S::from(mass) }
    }

    /// `I m`: the momentum (or force) of a motion.
    #[inline(always)]
    pub(crate) fn apply(&self, m: Motion<S>) -> Force<S> {
        Force {
            torque: self.aa * m.angular + self.ax * m.x + self.ay * m.y,
            x: self.ax * m.angular + self.xx * m.x + self.xy * m.y,
            y: self.ay * m.angular + self.xy * m.x + self.yy * m.y,
        }
    }

    /// `I − u uᵀ / d` (the articulated inertia passed across a joint), given `1 / d`.
    #[inline(always)]
    pub(crate) fn minus_outer(&self, u: Force<S>, inverse_d: S) -> Self {
        let (a, x, y) = (u.torque * inverse_d, u.x * inverse_d, u.y * inverse_d);
        Self {
            aa: self.aa - u.torque * a,
            ax: self.ax - u.torque * x,
            ay: self.ay - u.torque * y,
            xx: self.xx - u.x * x,
            xy: self.xy - u.x * y,
            yy: self.yy - u.y * y,
        }
    }

    /// `self += other`.
    #[inline(always)]
    pub(crate) fn add_assign(&mut self, other: &Inertia<S>) {
        self.aa += other.aa;
        self.ax += other.ax;
        self.ay += other.ay;
        self.xx += other.xx;
        self.xy += other.xy;
        self.yy += other.yy;
    }
}

impl<S: Scalar> RigidInertia<S> {
    /// A body in its centre-of-mass frame.
    pub(crate) fn body(mass: f64, inertia: f64) -> Self {
        Self { mass: S::from(mass), hx: S::zero(), hy: S::zero(), about_origin: S::from(inertia) }
    }

    /// The quadratic form `sᵀ I s`.
    #[inline(always)]
    pub(crate) fn quadratic(&self, s: Motion<S>) -> S {
        let moment = self.hx * s.y - self.hy * s.x;
        s.angular * (self.about_origin * s.angular + moment + moment) + self.mass * (s.x * s.x + s.y * s.y)
    }

    /// `self += other`.
    #[inline(always)]
    pub(crate) fn add_assign(&mut self, other: &RigidInertia<S>) {
        self.mass += other.mass;
        self.hx += other.hx;
        self.hy += other.hy;
        self.about_origin += other.about_origin;
    }
}

impl<S: Scalar> Translation<S> {
    /// `child_from_parent · m`: `ω' = ω`, `v' = v + ω ẑ × r` (the velocity of the body-fixed
    /// point at the child's origin), `ẑ × r = (−y, x)` (RBDA's planar `plnr` without rotation).
    #[inline(always)]
    pub(crate) fn motion(&self, m: Motion<S>) -> Motion<S> {
        Motion { angular: m.angular, x: m.x - m.angular * self.y, y: m.y + m.angular * self.x }
    }

    /// `child_from_parentᵀ · f`: a child-frame force in the parent frame, `f_p = f`,
    /// `τ_p = τ + r × f`.
    #[inline(always)]
    pub(crate) fn force_to_parent(&self, f: Force<S>) -> Force<S> {
        Force { torque: f.torque + self.x * f.y - self.y * f.x, x: f.x, y: f.y }
    }

    /// `Xᵀ I X` with `X = child_from_parent`: a child-frame inertia in the parent frame.
    /// Blocks `X = [[1, 0], [h, 1]]`, `h = (−y, x)`, `I = [[i₀₀, iᵀ], [i, J]]`, `w = i + J h`:
    /// `Xᵀ I X = [[i₀₀ + iᵀh + hᵀw, wᵀ], [w, J]]`.
    #[inline(always)]
    pub(crate) fn inertia_to_parent(&self, i: &Inertia<S>) -> Inertia<S> {
        let (hx, hy) = (-self.y, self.x);
        let (wx, wy) = (i.ax + i.xx * hx + i.xy * hy, i.ay + i.xy * hx + i.yy * hy);
        Inertia { aa: i.aa + (i.ax + wx) * hx + (i.ay + wy) * hy, ax: wx, ay: wy, xx: i.xx, xy: i.xy, yy: i.yy }
    }

    /// [`inertia_to_parent`](Self::inertia_to_parent) of a rigid inertia: the centre of mass
    /// moves by `r`, `h' = h + m r`, `I_O' = I_O + 2 r·h + m |r|²`.
    #[inline(always)]
    pub(crate) fn rigid_inertia_to_parent(&self, i: &RigidInertia<S>) -> RigidInertia<S> {
        let (mx, my) = (i.mass * self.x, i.mass * self.y);
        let dot = self.x * i.hx + self.y * i.hy;
        RigidInertia {
            mass: i.mass,
            hx: i.hx + mx,
            hy: i.hy + my,
            about_origin: i.about_origin + dot + dot + mx * self.x + my * self.y,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix3, Vector3};

    fn matrix(x: &Translation<f64>) -> Matrix3<f64> {
        // Columns: images of the unit motions.
        let e = |m: Motion<f64>| {
            let v = x.motion(m);
            Vector3::new(v.angular, v.x, v.y)
        };
        Matrix3::from_columns(&[
            e(Motion { angular: 1.0, x: 0.0, y: 0.0 }),
            e(Motion { angular: 0.0, x: 1.0, y: 0.0 }),
            e(Motion { angular: 0.0, x: 0.0, y: 1.0 }),
        ])
    }

    fn transform() -> Translation<f64> {
        Translation { x: 0.3, y: -1.2 }
    }

    /// The force transform is the transpose of the motion transform (power is invariant), and
    /// the inertia congruence is `Xᵀ I X`.
    #[test]
    fn force_and_inertia_transforms_are_the_transposes_of_the_motion_transform() {
        let x = transform();
        let m = matrix(&x);
        let f = Force { torque: 0.4, x: -1.1, y: 2.3 };
        let fp = x.force_to_parent(f);
        let expected = m.transpose() * Vector3::new(f.torque, f.x, f.y);
        assert!((Vector3::new(fp.torque, fp.x, fp.y) - expected).amax() < 1e-15);
        let i = Inertia { aa: 2.0, ax: 0.3, ay: -0.4, xx: 1.5, xy: 0.2, yy: 1.1 };
        let im = Matrix3::new(i.aa, i.ax, i.ay, i.ax, i.xx, i.xy, i.ay, i.xy, i.yy);
        let expected = m.transpose() * im * m;
        let got = x.inertia_to_parent(&i);
        let got = Matrix3::new(got.aa, got.ax, got.ay, got.ax, got.xx, got.xy, got.ay, got.xy, got.yy);
        assert!((got - expected).amax() < 1e-14, "{got} vs {expected}");
        // The compact rigid form transforms as its matrix does.
        let rigid = RigidInertia { mass: 1.5, hx: 0.4, hy: -0.3, about_origin: 2.0 };
        let matrix =
            |r: &RigidInertia<f64>| Matrix3::new(r.about_origin, -r.hy, r.hx, -r.hy, r.mass, 0.0, r.hx, 0.0, r.mass);
        let expected = m.transpose() * matrix(&rigid) * m;
        let got = matrix(&x.rigid_inertia_to_parent(&rigid));
        assert!((got - expected).amax() < 1e-14, "{got} vs {expected}");
        let v = Motion { angular: 0.7, x: -1.2, y: 0.4 };
        let quadratic = Vector3::new(v.angular, v.x, v.y).dot(&(matrix(&rigid) * Vector3::new(v.angular, v.x, v.y)));
        assert!((rigid.quadratic(v) - quadratic).abs() < 1e-14);
    }

    /// The child's origin moves with `v + ω ẑ × r`, and the cross product is RBDA's planar `crm`.
    #[test]
    fn motion_transform_and_cross_product_match_the_planar_formulas() {
        let r = transform();
        let moved = r.motion(Motion { angular: 2.0, x: 0.5, y: -0.25 });
        assert_eq!(moved, Motion { angular: 2.0, x: 0.5 - 2.0 * r.y, y: -0.25 + 2.0 * r.x });
        let v = Motion { angular: 0.8, x: -0.3, y: 1.7 };
        let crm = Matrix3::new(0.0, 0.0, 0.0, v.y, 0.0, -v.angular, -v.x, v.angular, 0.0);
        let m = Motion { angular: -1.3, x: 0.6, y: 0.25 };
        let got = v.cross_motion(m);
        let expected = crm * Vector3::new(m.angular, m.x, m.y);
        assert!((Vector3::new(got.angular, got.x, got.y) - expected).amax() < 1e-15);
    }
}
