//! The last step before printing: squares completed and linear terms factored, as a textbook
//! writes a spring's energy and force. `½ k r² − k L₀ r + ½ k L₀²` is `½ k (r − L₀)²`, and in
//! the equations `−k r + k L₀` is `−k (r − L₀)`.
//!
//! Both rewrite only terms that are a coordinate to a power times factors that do not move, and
//! only where every term of the completed form is there with its coefficient: the result is the
//! same polynomial. The completed sums are atoms (powers of sums), which the algebra does not
//! expand again, so this runs after every simplification.

use super::algebra::{Atom, Monomial, Poly, Rational, Symbol, Unsupported};

type R<T> = Result<T, Unsupported>;

/// The terms of `p` that are `s^k` times factors free of everything in `moving` (for `k = 0`:
/// the terms free of it altogether), with `s^k` taken out.
fn terms_in(p: &Poly, s: Symbol, k: i32, moving: &dyn Fn(Symbol) -> bool) -> Poly {
    let mut out = Poly::zero();
    for (m, &c) in &p.0 {
        let power = m.get(&Atom::Sym(s)).copied().unwrap_or(0);
        let rest_still = m.iter().all(|(a, _)| *a == Atom::Sym(s) || !a.contains(&moving));
        if power == k && rest_still {
            let mut rest = m.clone();
            rest.remove(&Atom::Sym(s));
            out.0.insert(rest, c);
        }
    }
    out
}

/// Whether every term of `part` is a term of `p` with the same coefficient.
fn holds(p: &Poly, part: &Poly) -> bool {
    !part.is_zero() && part.0.iter().all(|(m, c)| p.0.get(m) == Some(c))
}

/// `(s + d)^k` as one atom.
fn power_of_sum(s: Symbol, d: &Poly, k: i128) -> R<Poly> {
    Ok(Poly::atom(Atom::Pow(Box::new(Poly::sym(s).add(d)?), Rational::int(k))))
}

/// `p` with `a s² + b s + a d²` written `a (s + d)²`, `d = b/(2a)`, for a coefficient `a` of one
/// term that divides `b`; the `d` of each square completed.
fn complete_squares(
    p: &Poly,
    coordinates: &[Symbol],
    moving: &dyn Fn(Symbol) -> bool,
) -> R<(Poly, Vec<(Symbol, Poly)>)> {
    let mut p = p.clone();
    let mut shifts = Vec::new();
    for &s in coordinates {
        let (a, b) = (terms_in(&p, s, 2, moving), terms_in(&p, s, 1, moving));
        if a.0.len() != 1 || b.is_zero() {
            continue;
        }
        let (a_monomial, &alpha) = a.0.iter().next().expect("one term");
        // d = b / (2a), term by term: a's factors must divide each of b's.
        let mut d = Poly::zero();
        let mut divides = true;
        for (m, &beta) in &b.0 {
            let mut q: Monomial = m.clone();
            for (atom, &e) in a_monomial {
                let left = q.get(atom).copied().unwrap_or(0) - e;
                if left < 0 {
                    divides = false;
                }
                if left == 0 {
                    q.remove(atom);
                } else {
                    q.insert(atom.clone(), left);
                }
            }
            let coefficient = beta.checked_mul(alpha.checked_mul(Rational::int(2))?.recip()?)?;
            d = d.add(&Poly(std::collections::BTreeMap::from([(q, coefficient)])))?;
        }
        if !divides {
            continue;
        }
        let constant = a.mul(&d.mul(&d)?)?;
        if !holds(&terms_in(&p, s, 0, moving), &constant) {
            continue;
        }
        let square = Poly::sym(s).powi(2)?;
        let expanded = a.mul(&square)?.add(&b.mul(&Poly::sym(s))?)?.add(&constant)?;
        p = p.sub(&expanded)?.add(&a.mul(&power_of_sum(s, &d, 2)?)?)?;
        shifts.push((s, d));
    }
    Ok((p, shifts))
}

/// `p` with `b s + b d` written `b (s + d)` for each `(s, d)` of `shifts`, where every term of
/// `b d` is in `p`.
fn factor_shifts(p: &Poly, shifts: &[(Symbol, Poly)], moving: &dyn Fn(Symbol) -> bool) -> R<Poly> {
    let mut p = p.clone();
    for (s, d) in shifts {
        let b = terms_in(&p, *s, 1, moving);
        if b.is_zero() {
            continue;
        }
        let shifted = b.mul(d)?;
        if !holds(&p, &shifted) {
            continue;
        }
        p = p.sub(&b.mul(&Poly::sym(*s))?)?.sub(&shifted)?.add(&b.mul(&power_of_sum(*s, d, 1)?)?)?;
    }
    Ok(p)
}

/// Squares completed in the energies and the same shifts factored in the equations.
pub(crate) struct Presenter<'a> {
    coordinates: Vec<Symbol>,
    moving: &'a dyn Fn(Symbol) -> bool,
    shifts: Vec<(Symbol, Poly)>,
}

impl<'a> Presenter<'a> {
    /// For the coordinates `coordinates`, with `moving` what moves.
    pub fn new(coordinates: Vec<Symbol>, moving: &'a dyn Fn(Symbol) -> bool) -> Self {
        Self { coordinates, moving, shifts: Vec::new() }
    }

    /// An energy: its squares completed, and their shifts kept for [`Self::force`].
    pub fn energy(&mut self, p: &Poly) -> R<Poly> {
        let (out, shifts) = complete_squares(p, &self.coordinates, self.moving)?;
        for (s, d) in shifts {
            if !self.shifts.iter().any(|(t, _)| *t == s) {
                self.shifts.push((s, d));
            }
        }
        Ok(out)
    }

    /// A side of an equation: the energies' shifts factored.
    pub fn force(&self, p: &Poly) -> R<Poly> {
        factor_shifts(p, &self.shifts, self.moving)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_spring_energy_is_a_square_and_its_force_a_product() {
        // Symbols: 0 = r (moves), 1 = k, 2 = L.
        let moving = |s: Symbol| s == 0;
        let (r, k, l) = (Poly::sym(0), Poly::sym(1), Poly::sym(2));
        let half = Rational::new(1, 2).unwrap();
        let stretch = r.sub(&l).unwrap();
        let energy = k.mul(&stretch.mul(&stretch).unwrap()).unwrap().scale(half).unwrap();
        let extra = Poly::sym(1).mul(&Poly::sym(2)).unwrap(); // k L, a constant that stays
        let mut presenter = Presenter::new(vec![0], &moving);
        let printed = presenter.energy(&energy.add(&extra).unwrap()).unwrap();
        let expected = k.mul(&power_of_sum(0, &l.neg(), 2).unwrap()).unwrap().scale(half).unwrap().add(&extra).unwrap();
        assert_eq!(printed, expected);
        let force = k.mul(&stretch).unwrap().neg();
        assert_eq!(presenter.force(&force).unwrap(), k.mul(&power_of_sum(0, &l.neg(), 1).unwrap()).unwrap().neg());
        // Not a square: left alone.
        let other = k.mul(&r.mul(&r).unwrap()).unwrap().add(&k.mul(&r).unwrap()).unwrap();
        assert_eq!(Presenter::new(vec![0], &moving).energy(&other).unwrap(), other);
    }
}
