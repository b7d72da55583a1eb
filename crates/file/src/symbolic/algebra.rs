//! Exact polynomial algebra over "atoms" (symbols, functions of polynomials, powers of sums),
//! with rational coefficients: enough to differentiate a scene file's expressions and write the
//! results as a textbook does.

use crate::expr::Function;
use std::collections::BTreeMap;
use std::fmt;

/// A coefficient: an exact rational number `n / d` (`d > 0`, lowest terms) while it fits in
/// 128 bits, else a float ([`Rational::Float`]: sixteen significant digits of a geometry given
/// in decimals, whose exact products outgrow any fixed width).
#[derive(Clone, Copy, Debug)]
pub enum Rational {
    /// `n / d`.
    Exact {
        /// Numerator.
        n: i128,
        /// Denominator, positive.
        d: i128,
    },
    /// A value beyond exact 128-bit arithmetic.
    Float(f64),
}

impl Rational {
    /// What orders, compares and hashes it: exact values first.
    fn key(&self) -> (u8, i128, i128, u64) {
        match *self {
            Rational::Exact { n, d } => (0, n, d, 0),
            Rational::Float(v) => (1, 0, 0, v.to_bits()),
        }
    }
}

impl PartialEq for Rational {
    fn eq(&self, other: &Self) -> bool {
        self.key() == other.key()
    }
}

impl Eq for Rational {}

impl PartialOrd for Rational {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Rational {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        match (self, other) {
            (Rational::Float(a), Rational::Float(b)) => a.total_cmp(b),
            _ => self.key().cmp(&other.key()),
        }
    }
}

impl std::hash::Hash for Rational {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.key().hash(state);
    }
}

/// Why an expression has no exact symbolic form here.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Unsupported(pub String);

impl fmt::Display for Unsupported {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

fn gcd(a: i128, b: i128) -> i128 {
    let (mut a, mut b) = (a.abs(), b.abs());
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

impl Rational {
    /// `n / d`.
    pub fn new(n: i128, d: i128) -> Result<Self, Unsupported> {
        if d == 0 {
            return Err(Unsupported("division by zero".into()));
        }
        let g = gcd(n, d).max(1);
        let s = if d < 0 { -1 } else { 1 };
        Ok(Self::Exact { n: s * n / g, d: s * d / g })
    }

    /// An integer.
    pub const fn int(n: i128) -> Self {
        Self::Exact { n, d: 1 }
    }

    /// The exact value of a decimal number as written (its shortest round-trip form), or the
    /// float itself where that does not fit in 128 bits.
    pub fn from_f64(v: f64) -> Result<Self, Unsupported> {
        if !v.is_finite() {
            return Err(Unsupported(format!("{v} is not a number")));
        }
        Ok(Self::decimal(&format!("{v:e}")).unwrap_or(Self::Float(v)))
    }

    /// The decimal `text` (`d.ddde±k`) as an exact fraction, if it fits.
    fn decimal(text: &str) -> Option<Self> {
        let (mantissa, exponent) = text.split_once('e').unwrap_or((text, "0"));
        let exponent: i32 = exponent.parse().ok()?;
        let (int, frac) = mantissa.split_once('.').unwrap_or((mantissa, ""));
        let digits: i128 = format!("{int}{frac}").parse().ok()?;
        let scale = exponent - frac.len() as i32;
        let ten = 10_i128.checked_pow(scale.unsigned_abs())?;
        if scale >= 0 { Some(Self::int(digits.checked_mul(ten)?)) } else { Self::new(digits, ten).ok() }
    }

    /// A float result: exact again when it is within four units in the last place of a
    /// decimal of twelve significant digits (`0.75000000000000011` → ¾), which keeps sums of
    /// squared sines and cosines of decimal angles printable.
    fn float(v: f64) -> Self {
        if v == 0.0 {
            return Self::int(0);
        }
        let short = format!("{v:.11e}");
        match short.parse::<f64>() {
            Ok(r) if (r - v).abs() <= 4.0 * f64::EPSILON * v.abs() => Self::decimal(&short).unwrap_or(Self::Float(v)),
            _ => Self::Float(v),
        }
    }

    /// `(n, d)` of an exact value.
    pub fn exact(self) -> Option<(i128, i128)> {
        match self {
            Self::Exact { n, d } => Some((n, d)),
            Self::Float(_) => None,
        }
    }

    /// Below zero?
    pub fn is_negative(self) -> bool {
        match self {
            Self::Exact { n, .. } => n < 0,
            Self::Float(v) => v < 0.0,
        }
    }

    /// Zero?
    pub fn is_zero(self) -> bool {
        match self {
            Self::Exact { n, .. } => n == 0,
            Self::Float(v) => v == 0.0,
        }
    }

    /// As a float.
    pub fn to_f64(self) -> f64 {
        match self {
            Self::Exact { n, d } => n as f64 / d as f64,
            Self::Float(v) => v,
        }
    }

    /// `self + other`.
    pub fn checked_add(self, other: Self) -> Result<Self, Unsupported> {
        if let (Self::Exact { n: a, d: b }, Self::Exact { n: c, d }) = (self, other) {
            let n = a.checked_mul(d).and_then(|x| c.checked_mul(b).and_then(|y| x.checked_add(y)));
            if let (Some(n), Some(d)) = (n, b.checked_mul(d)) {
                return Self::new(n, d);
            }
        }
        Ok(Self::float(self.to_f64() + other.to_f64()))
    }

    /// `self · other`.
    pub fn checked_mul(self, other: Self) -> Result<Self, Unsupported> {
        if let (Self::Exact { n: a, d: b }, Self::Exact { n: c, d }) = (self, other)
            && let (Some(n), Some(d)) = (a.checked_mul(c), b.checked_mul(d))
        {
            return Self::new(n, d);
        }
        Ok(Self::float(self.to_f64() * other.to_f64()))
    }

    /// `1 / self`.
    pub fn recip(self) -> Result<Self, Unsupported> {
        match self {
            Self::Exact { n, d } => Self::new(d, n),
            Self::Float(v) => Ok(Self::float(1.0 / v)),
        }
    }
}

impl std::ops::Neg for Rational {
    type Output = Self;

    /// `−self`.
    fn neg(self) -> Self {
        match self {
            Self::Exact { n, d } => Self::Exact { n: -n, d },
            Self::Float(v) => Self::Float(-v),
        }
    }
}

/// A symbol's index in the table the caller keeps (parameters, coordinates, rates, …).
pub type Symbol = u32;

/// A factor that is not a product: a symbol, a function of a polynomial, a power of a sum.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Atom {
    /// A symbol.
    Sym(Symbol),
    /// `f(p)` for a one-argument function other than a power.
    Fun(Function, Box<Poly>),
    /// `atan2(y, x)`.
    Atan2(Box<Poly>, Box<Poly>),
    /// `p^r` of a polynomial that is not one monomial, for a non-integer or negative `r`.
    Pow(Box<Poly>, Rational),
}

/// A product of atoms with integer exponents (none zero), in order.
pub type Monomial = BTreeMap<Atom, i32>;

/// A sum of monomials with non-zero rational coefficients.
#[derive(Clone, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Poly(pub BTreeMap<Monomial, Rational>);

type R<T> = Result<T, Unsupported>;

impl Poly {
    /// 0.
    pub fn zero() -> Self {
        Self::default()
    }

    /// A constant.
    pub fn constant(c: Rational) -> Self {
        let mut p = Self::zero();
        if !c.is_zero() {
            p.0.insert(Monomial::new(), c);
        }
        p
    }

    /// One atom.
    pub fn atom(a: Atom) -> Self {
        Self(BTreeMap::from([(Monomial::from([(a, 1)]), Rational::int(1))]))
    }

    /// A symbol.
    pub fn sym(s: Symbol) -> Self {
        Self::atom(Atom::Sym(s))
    }

    /// Whether it is 0.
    pub fn is_zero(&self) -> bool {
        self.0.is_empty()
    }

    /// The constant it is, if it is one.
    pub fn as_constant(&self) -> Option<Rational> {
        match self.0.len() {
            0 => Some(Rational::int(0)),
            1 => self.0.get(&Monomial::new()).copied(),
            _ => None,
        }
    }

    fn add_term(&mut self, m: Monomial, c: Rational) -> R<()> {
        let sum = match self.0.get(&m) {
            Some(&old) => old.checked_add(c)?,
            None => c,
        };
        if sum.is_zero() {
            self.0.remove(&m);
        } else {
            self.0.insert(m, sum);
        }
        Ok(())
    }

    /// `self + other`.
    pub fn add(&self, other: &Poly) -> R<Poly> {
        let mut out = self.clone();
        for (m, &c) in &other.0 {
            out.add_term(m.clone(), c)?;
        }
        Ok(out)
    }

    /// `self − other`.
    pub fn sub(&self, other: &Poly) -> R<Poly> {
        self.add(&other.neg())
    }

    /// `−self`.
    pub fn neg(&self) -> Poly {
        Poly(self.0.iter().map(|(m, c)| (m.clone(), -*c)).collect())
    }

    /// `c · self`.
    pub fn scale(&self, c: Rational) -> R<Poly> {
        let mut out = Poly::zero();
        for (m, &k) in &self.0 {
            out.add_term(m.clone(), k.checked_mul(c)?)?;
        }
        Ok(out)
    }

    /// `self · other`.
    pub fn mul(&self, other: &Poly) -> R<Poly> {
        let mut out = Poly::zero();
        for (ma, &ca) in &self.0 {
            for (mb, &cb) in &other.0 {
                let mut m = ma.clone();
                for (atom, &e) in mb {
                    let total = m.get(atom).copied().unwrap_or(0) + e;
                    if total == 0 {
                        m.remove(atom);
                    } else {
                        m.insert(atom.clone(), total);
                    }
                }
                let c = ca.checked_mul(cb)?;
                // A root raised to a multiple of its index is a power of its radicand:
                // (√p)² = p (a real square root's radicand is not negative).
                let whole = m.iter().find_map(|(a, &e)| match a {
                    Atom::Pow(p, r) => match r.exact() {
                        Some((1, b)) if b > 1 && e % b as i32 == 0 => Some((a.clone(), p.clone(), e / b as i32)),
                        _ => None,
                    },
                    _ => None,
                });
                match whole {
                    None => out.add_term(m, c)?,
                    Some((atom, radicand, k)) => {
                        m.remove(&atom);
                        out = out.add(&Poly(BTreeMap::from([(m, c)])).mul(&radicand.powi(k)?)?)?;
                    }
                }
            }
        }
        Ok(out)
    }

    /// `self^k` for an integer `k` (a negative power of a sum is an atom).
    pub fn powi(&self, k: i32) -> R<Poly> {
        if k >= 0 {
            let mut out = Poly::constant(Rational::int(1));
            for _ in 0..k {
                out = out.mul(self)?;
            }
            return Ok(out);
        }
        match self.0.len() {
            0 => Err(Unsupported("a negative power of zero".into())),
            1 => {
                // One monomial: invert it.
                let (m, &c) = self.0.iter().next().expect("one term");
                let inverse = Poly(BTreeMap::from([(m.iter().map(|(a, &e)| (a.clone(), -e)).collect(), c.recip()?)]));
                inverse.powi(-k)
            }
            _ => Ok(Poly::atom(Atom::Pow(Box::new(self.clone()), Rational::int(k as i128)))),
        }
    }

    /// `self^r` for a rational `r`.
    pub fn powr(&self, r: Rational) -> R<Poly> {
        if let Some((n, 1)) = r.exact()
            && n.abs() <= 64
        {
            return self.powi(n as i32);
        }
        if self.is_zero() {
            return Ok(Poly::zero());
        }
        // p^(a/b) = (p^(1/b))^a: one atom per root, whose integer powers multiply, cancel
        // (√p / √p = 1) and reduce ((√p)² = p).
        if let Some((a, b)) = r.exact()
            && b > 1
            && b <= 64
            && a.abs() <= 64
            && a != 1
        {
            return Poly::atom(Atom::Pow(Box::new(self.clone()), Rational::new(1, b)?)).powi(a as i32);
        }
        // A monomial whose exponents r divides evenly stays a monomial (√(a²) is not simplified
        // to a: signs are unknown, so only even powers under a positive coefficient would be).
        Ok(Poly::atom(Atom::Pow(Box::new(self.clone()), r)))
    }

    /// `f(self)`, with the sign of odd functions taken out of the argument and the values at 0.
    pub fn apply(&self, f: Function) -> R<Poly> {
        let odd = matches!(f, Function::Sin | Function::Tan | Function::Asin | Function::Atan | Function::Sinh);
        let even = matches!(f, Function::Cos | Function::Cosh | Function::Abs);
        if self.is_zero() {
            return Ok(match f {
                Function::Cos | Function::Cosh | Function::Exp => Poly::constant(Rational::int(1)),
                Function::Acos => return Err(Unsupported("acos(0) would print as π/2".into())),
                Function::Ln => return Err(Unsupported("ln(0)".into())),
                _ => Poly::zero(),
            });
        }
        if f == Function::Sqrt {
            return self.powr(Rational::new(1, 2)?);
        }
        let negative = self.0.values().next().is_some_and(|c| c.is_negative());
        if negative && (odd || even) {
            let inner = Poly::atom(Atom::Fun(f, Box::new(self.neg())));
            return Ok(if odd { inner.neg() } else { inner });
        }
        Ok(Poly::atom(Atom::Fun(f, Box::new(self.clone()))))
    }

    /// `∂self/∂s`.
    pub fn diff(&self, s: Symbol) -> R<Poly> {
        let mut out = Poly::zero();
        for (m, &c) in &self.0 {
            for (atom, &e) in m {
                let d_atom = atom.diff(s)?;
                if d_atom.is_zero() {
                    continue;
                }
                // e · atom^(e−1) · rest · d(atom)
                let mut rest = m.clone();
                if e == 1 {
                    rest.remove(atom);
                } else {
                    rest.insert(atom.clone(), e - 1);
                }
                let term = Poly(BTreeMap::from([(rest, c.checked_mul(Rational::int(e as i128))?)]));
                out = out.add(&term.mul(&d_atom)?)?;
            }
        }
        Ok(out)
    }

    /// Replace symbol `s` by `value` everywhere (inside functions too).
    pub fn substitute(&self, s: Symbol, value: &Poly) -> R<Poly> {
        let mut out = Poly::zero();
        for (m, &c) in &self.0 {
            let mut term = Poly::constant(c);
            for (atom, &e) in m {
                term = term.mul(&atom.substitute(s, value)?.powi(e)?)?;
            }
            out = out.add(&term)?;
        }
        Ok(out)
    }

    /// Whether any symbol in `set` occurs.
    pub fn contains(&self, set: &impl Fn(Symbol) -> bool) -> bool {
        self.0.keys().any(|m| m.keys().any(|a| a.contains(set)))
    }

    /// Apply the textbook identities until none applies: `sin²a + cos²a = 1`,
    /// `cos a cos b ± sin a sin b = cos(a ∓ b)`, `sin a cos b ± cos a sin b = sin(a ± b)`.
    pub fn simplify(&self) -> R<Poly> {
        let mut p = self.simplify_inside()?;
        while let Some(next) = p.pythagoras()?.or(p.angle_sum()?) {
            p = next;
        }
        Ok(p)
    }

    fn simplify_inside(&self) -> R<Poly> {
        let mut out = Poly::zero();
        for (m, &c) in &self.0 {
            let mut term = Poly::constant(c);
            for (atom, &e) in m {
                let a = match atom {
                    Atom::Sym(_) => Poly::atom(atom.clone()),
                    Atom::Fun(f, p) => p.simplify()?.apply(*f)?,
                    Atom::Atan2(y, x) => Poly::atom(Atom::Atan2(Box::new(y.simplify()?), Box::new(x.simplify()?))),
                    Atom::Pow(p, r) => p.simplify()?.powr(*r)?,
                };
                term = term.mul(&a.powi(e)?)?;
            }
            out = out.add(&term)?;
        }
        Ok(out)
    }

    /// One `k R sin²a + k R cos²a → k R`, or `k R − k R cos²a → k R sin²a` (and with sine and
    /// cosine exchanged).
    fn pythagoras(&self) -> R<Option<Poly>> {
        for (m, &c) in &self.0 {
            for (atom, &e) in m {
                let (Atom::Fun(f @ (Function::Sin | Function::Cos), arg), 2) = (atom, e) else { continue };
                let mut rest = m.clone();
                rest.remove(atom);
                if self.0.get(&rest) == Some(&-c) {
                    // −k R cos²a + k R = k R sin²a
                    let other = if *f == Function::Sin { Function::Cos } else { Function::Sin };
                    let mut out = self.clone();
                    out.0.remove(m);
                    out.0.remove(&rest);
                    let mut square = rest.clone();
                    square.insert(Atom::Fun(other, arg.clone()), 2);
                    out.add_term(square, -c)?;
                    return Ok(Some(out));
                }
                if *f != Function::Sin {
                    continue;
                }
                let mut partner = m.clone();
                partner.remove(atom);
                partner.insert(Atom::Fun(Function::Cos, arg.clone()), 2);
                if self.0.get(&partner) == Some(&c) {
                    let mut rest = m.clone();
                    rest.remove(atom);
                    let mut out = self.clone();
                    out.0.remove(m);
                    out.0.remove(&partner);
                    out.add_term(rest, c)?;
                    return Ok(Some(out));
                }
            }
        }
        Ok(None)
    }

    /// One pair of terms that is the cosine or sine of a sum or difference.
    fn angle_sum(&self) -> R<Option<Poly>> {
        let trig = |m: &Monomial, f: Function| -> Vec<Poly> {
            m.iter()
                .filter_map(|(a, &e)| match a {
                    Atom::Fun(g, p) if *g == f && e == 1 => Some((**p).clone()),
                    _ => None,
                })
                .collect()
        };
        let without = |m: &Monomial, drops: &[(Function, &Poly)]| -> Monomial {
            let mut r = m.clone();
            for (f, p) in drops {
                r.remove(&Atom::Fun(*f, Box::new((*p).clone())));
            }
            r
        };
        for (m, &c) in &self.0 {
            let (cosines, sines) = (trig(m, Function::Cos), trig(m, Function::Sin));
            // cos a cos b with sin a sin b: cos(a − b) (same sign) or cos(a + b) (opposite).
            for (i, a) in cosines.iter().enumerate() {
                for b in &cosines[i + 1..] {
                    let rest = without(m, &[(Function::Cos, a), (Function::Cos, b)]);
                    let mut partner = rest.clone();
                    partner.insert(Atom::Fun(Function::Sin, Box::new(a.clone())), 1);
                    partner.insert(Atom::Fun(Function::Sin, Box::new(b.clone())), 1);
                    if let Some(&k) = self.0.get(&partner) {
                        let angle = if k == c {
                            a.sub(b)?
                        } else if k == -c {
                            a.add(b)?
                        } else {
                            continue;
                        };
                        return Ok(Some(self.replace(&[m, &partner], &rest, c, angle.apply(Function::Cos)?)?));
                    }
                }
            }
            // sin a cos b with ± cos a sin b: sin(a ± b).
            for a in &sines {
                for b in &cosines {
                    if a == b {
                        continue;
                    }
                    let rest = without(m, &[(Function::Sin, a), (Function::Cos, b)]);
                    let mut partner = rest.clone();
                    partner.insert(Atom::Fun(Function::Cos, Box::new(a.clone())), 1);
                    partner.insert(Atom::Fun(Function::Sin, Box::new(b.clone())), 1);
                    if let Some(&k) = self.0.get(&partner) {
                        let angle = if k == c {
                            a.add(b)?
                        } else if k == -c {
                            a.sub(b)?
                        } else {
                            continue;
                        };
                        return Ok(Some(self.replace(&[m, &partner], &rest, c, angle.apply(Function::Sin)?)?));
                    }
                }
            }
        }
        Ok(None)
    }

    /// Without the monomials `drop`, plus `c · rest · value`.
    fn replace(&self, drop: &[&Monomial], rest: &Monomial, c: Rational, value: Poly) -> R<Poly> {
        let mut out = self.clone();
        for m in drop {
            out.0.remove(*m);
        }
        out.add(&Poly(BTreeMap::from([(rest.clone(), c)])).mul(&value)?)
    }
}

impl Atom {
    fn diff(&self, s: Symbol) -> R<Poly> {
        let one = || Poly::constant(Rational::int(1));
        Ok(match self {
            Atom::Sym(t) => {
                if *t == s {
                    one()
                } else {
                    Poly::zero()
                }
            }
            Atom::Fun(f, p) => {
                let dp = p.diff(s)?;
                if dp.is_zero() {
                    return Ok(Poly::zero());
                }
                let outer = match f {
                    Function::Sin => p.apply(Function::Cos)?,
                    Function::Cos => p.apply(Function::Sin)?.neg(),
                    Function::Tan => one().add(&p.apply(Function::Tan)?.powi(2)?)?,
                    Function::Sinh => p.apply(Function::Cosh)?,
                    Function::Cosh => p.apply(Function::Sinh)?,
                    Function::Exp => p.apply(Function::Exp)?,
                    Function::Ln => p.powi(-1)?,
                    Function::Sqrt => p.powr(Rational::new(-1, 2)?)?.scale(Rational::new(1, 2)?)?,
                    Function::Asin | Function::Acos => {
                        let root = one().sub(&p.mul(p)?)?.powr(Rational::new(-1, 2)?)?;
                        if *f == Function::Asin { root } else { root.neg() }
                    }
                    Function::Atan => one().add(&p.mul(p)?)?.powi(-1)?,
                    Function::Abs | Function::Atan2 => {
                        return Err(Unsupported(format!("`{}` has no derivative printed here", f.name())));
                    }
                };
                outer.mul(&dp)?
            }
            Atom::Atan2(y, x) => {
                let (dy, dx) = (y.diff(s)?, x.diff(s)?);
                if dy.is_zero() && dx.is_zero() {
                    return Ok(Poly::zero());
                }
                let num = x.mul(&dy)?.sub(&y.mul(&dx)?)?;
                num.mul(&x.mul(x)?.add(&y.mul(y)?)?.powi(-1)?)?
            }
            Atom::Pow(p, r) => {
                let dp = p.diff(s)?;
                if dp.is_zero() {
                    return Ok(Poly::zero());
                }
                p.powr(r.checked_add(Rational::int(-1))?)?.scale(*r)?.mul(&dp)?
            }
        })
    }

    fn substitute(&self, s: Symbol, value: &Poly) -> R<Poly> {
        Ok(match self {
            Atom::Sym(t) if *t == s => value.clone(),
            Atom::Sym(_) => Poly::atom(self.clone()),
            Atom::Fun(f, p) => p.substitute(s, value)?.apply(*f)?,
            Atom::Atan2(y, x) => {
                Poly::atom(Atom::Atan2(Box::new(y.substitute(s, value)?), Box::new(x.substitute(s, value)?)))
            }
            Atom::Pow(p, r) => p.substitute(s, value)?.powr(*r)?,
        })
    }

    /// Whether any symbol in `set` occurs in it.
    pub fn contains(&self, set: &impl Fn(Symbol) -> bool) -> bool {
        match self {
            Atom::Sym(s) => set(*s),
            Atom::Fun(_, p) | Atom::Pow(p, _) => p.contains(set),
            Atom::Atan2(y, x) => y.contains(set) || x.contains(set),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(n: i128, d: i128) -> Rational {
        Rational::new(n, d).unwrap()
    }

    #[test]
    fn rationals_are_exact() {
        assert_eq!(Rational::from_f64(0.1).unwrap(), q(1, 10));
        assert_eq!(Rational::from_f64(9.81).unwrap(), q(981, 100));
        assert_eq!(Rational::from_f64(1e-3).unwrap(), q(1, 1000));
        assert_eq!(Rational::from_f64(2.5e3).unwrap(), Rational::int(2500));
        assert_eq!(q(1, 3).checked_add(q(1, 6)).unwrap(), q(1, 2));
        // Beyond 128 bits: the float, until a result is near a short decimal again.
        assert_eq!(Rational::from_f64(1e300).unwrap(), Rational::Float(1e300));
        let root = Rational::from_f64(0.8660254037844387).unwrap();
        let square = root.checked_mul(root).unwrap();
        assert!(square.exact().is_some());
        assert_eq!(square.checked_mul(square).unwrap(), q(9, 16));
    }

    #[test]
    fn textbook_identities() {
        let (a, b) = (Poly::sym(0), Poly::sym(1));
        let (sa, ca) = (a.apply(Function::Sin).unwrap(), a.apply(Function::Cos).unwrap());
        let (sb, cb) = (b.apply(Function::Sin).unwrap(), b.apply(Function::Cos).unwrap());
        // 3 m (sin²a + cos²a) = 3 m
        let m = Poly::sym(2).scale(Rational::int(3)).unwrap();
        let p = m.mul(&sa.powi(2).unwrap().add(&ca.powi(2).unwrap()).unwrap()).unwrap();
        assert_eq!(p.simplify().unwrap(), m);
        // m − m cos²a = m sin²a
        let p = m.sub(&m.mul(&ca.powi(2).unwrap()).unwrap()).unwrap();
        assert_eq!(p.simplify().unwrap(), m.mul(&sa.powi(2).unwrap()).unwrap());
        // cos a cos b + sin a sin b = cos(a − b); cos(b − a) is the same atom.
        let p = ca.mul(&cb).unwrap().add(&sa.mul(&sb).unwrap()).unwrap();
        assert_eq!(p.simplify().unwrap(), a.sub(&b).unwrap().apply(Function::Cos).unwrap());
        assert_eq!(b.sub(&a).unwrap().apply(Function::Cos).unwrap(), a.sub(&b).unwrap().apply(Function::Cos).unwrap());
        // sin a cos b − cos a sin b = sin(a − b) = −sin(b − a)
        let p = sa.mul(&cb).unwrap().sub(&ca.mul(&sb).unwrap()).unwrap();
        assert_eq!(p.simplify().unwrap(), b.sub(&a).unwrap().apply(Function::Sin).unwrap().neg());
    }

    #[test]
    fn derivatives() {
        let x = Poly::sym(0);
        // d/dx sin(x²) = 2x cos(x²)
        let d = x.powi(2).unwrap().apply(Function::Sin).unwrap().diff(0).unwrap();
        let expected =
            x.scale(Rational::int(2)).unwrap().mul(&x.powi(2).unwrap().apply(Function::Cos).unwrap()).unwrap();
        assert_eq!(d, expected);
        // d/dx (1 + x²)^(1/2) = x (1 + x²)^(−1/2)
        let s = Poly::constant(Rational::int(1)).add(&x.powi(2).unwrap()).unwrap();
        let d = s.powr(q(1, 2)).unwrap().diff(0).unwrap();
        assert_eq!(d, x.mul(&s.powr(q(-1, 2)).unwrap()).unwrap());
    }
}
