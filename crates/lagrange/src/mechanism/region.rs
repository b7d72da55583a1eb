//! Where a mechanism's model holds: inequality bounds on the state, declared by the mechanism
//! ([`Mechanism::admissible`](crate::Mechanism::admissible)) and checked by the integrators
//! (docs/method.md#admissible-regions).

use super::LagrangianFunction;
use crate::Error;
use std::fmt;

/// Which side of its limit a bounded quantity must stay on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// `value > limit`.
    Above,
    /// `value ≥ limit`.
    AtLeast,
    /// `value ≤ limit`.
    AtMost,
    /// `value < limit`.
    Below,
}

impl Side {
    /// Whether `value` lies on this side of `limit` (never for NaN).
    pub fn holds(self, value: f64, limit: f64) -> bool {
        match self {
            Side::Above => value > limit,
            Side::AtLeast => value >= limit,
            Side::AtMost => value <= limit,
            Side::Below => value < limit,
        }
    }
}

impl fmt::Display for Side {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Side::Above => ">",
            Side::AtLeast => "≥",
            Side::AtMost => "≤",
            Side::Below => "<",
        })
    }
}

/// Where a mechanism declares its admissible region, one bound per call
/// ([`Mechanism::admissible`](crate::Mechanism::admissible)): each bound names the quantity it
/// bounds (a coordinate, `rope length l − x`), its value at the state, the side and the limit.
///
/// The sink keeps the first bound that fails and allocates nothing until one does, so that a
/// check after every step of an integrator costs only the mechanism's own arithmetic.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bounds {
    declared: usize,
    failed: Option<Failed>,
}

/// The first bound that failed.
#[derive(Clone, Debug, PartialEq)]
struct Failed {
    quantity: String,
    side: Side,
    value: f64,
    limit: f64,
}

impl Bounds {
    /// No bound declared yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Bound `quantity` (its `value` at the state) to the `side` of `limit`.
    pub fn bound(&mut self, quantity: &str, value: f64, side: Side, limit: f64) {
        self.declared += 1;
        if self.failed.is_none() && !side.holds(value, limit) {
            self.failed = Some(Failed { quantity: quantity.to_string(), side, value, limit });
        }
    }

    /// `value > limit` (a polar radius: `r > 0`).
    pub fn above(&mut self, quantity: &str, value: f64, limit: f64) {
        self.bound(quantity, value, Side::Above, limit);
    }

    /// `value ≥ limit` (a rope segment's length: `≥ 0`).
    pub fn at_least(&mut self, quantity: &str, value: f64, limit: f64) {
        self.bound(quantity, value, Side::AtLeast, limit);
    }

    /// `value ≤ limit` (a block on an incline of length `L`: `≤ L`).
    pub fn at_most(&mut self, quantity: &str, value: f64, limit: f64) {
        self.bound(quantity, value, Side::AtMost, limit);
    }

    /// `value < limit`.
    pub fn below(&mut self, quantity: &str, value: f64, limit: f64) {
        self.bound(quantity, value, Side::Below, limit);
    }

    /// How many bounds were declared.
    pub fn declared(&self) -> usize {
        self.declared
    }

    /// Whether every bound declared so far holds.
    pub fn hold(&self) -> bool {
        self.failed.is_none()
    }

    /// [`Error::Inadmissible`] at time `t` for the first bound that failed, if one did.
    pub fn error(&self, t: f64) -> Option<Error> {
        let Failed { quantity, side, value, limit } = self.failed.as_ref()?;
        let bound = format!("{quantity} {side} {}", crate::error::compact(limit));
        Some(Error::Inadmissible {
            t,
            inside_until: None,
            quantity: quantity.clone(),
            bound,
            value: *value,
            limit: *limit,
        })
    }

    /// Check `(t, q, q̇)` against the admissible region of `system`: `Ok(false)` when it
    /// declares none, `Ok(true)` when the state lies inside.
    ///
    /// # Errors
    /// [`Error::Inadmissible`] naming the first bound that fails.
    pub fn check<F: LagrangianFunction + ?Sized>(system: &F, t: f64, q: &[f64], qdot: &[f64]) -> Result<bool, Error> {
        let mut bounds = Bounds::new();
        if !system.admissible(t, q, qdot, &mut bounds) {
            return Ok(false);
        }
        match bounds.error(t) {
            Some(error) => Err(error),
            None => Ok(true),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_failing_bound_is_kept_and_named_with_its_side() {
        let mut bounds = Bounds::new();
        bounds.above("r", 0.5, 0.0);
        assert!(bounds.hold());
        bounds.at_least("rope length l − x", -0.25, 0.0);
        bounds.at_most("x'", 3.0, 2.0);
        assert_eq!(bounds.declared(), 3);
        let error = bounds.error(1.5).unwrap();
        assert_eq!(
            error,
            Error::Inadmissible {
                t: 1.5,
                inside_until: None,
                quantity: "rope length l − x".into(),
                bound: "rope length l − x ≥ 0".into(),
                value: -0.25,
                limit: 0.0,
            }
        );
        assert_eq!(
            error.to_string(),
            "rope length l − x = -0.25 is outside the admissible region rope length l − x ≥ 0 at t = 1.5 s"
        );
    }

    #[test]
    fn sides_are_strict_or_not_and_nan_never_holds() {
        assert!(!Side::Above.holds(0.0, 0.0) && Side::AtLeast.holds(0.0, 0.0));
        assert!(Side::AtMost.holds(2.0, 2.0) && !Side::Below.holds(2.0, 2.0));
        for side in [Side::Above, Side::AtLeast, Side::AtMost, Side::Below] {
            assert!(!side.holds(f64::NAN, 0.0), "{side}");
        }
        let mut bounds = Bounds::new();
        bounds.below("v", 1e-20, 1e-20);
        assert_eq!(
            bounds.error(0.0).unwrap().to_string(),
            "v = 1e-20 is outside the admissible region v < 1e-20 at t = 0 s"
        );
    }
}
