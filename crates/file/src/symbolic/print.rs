//! Writing polynomials as a textbook does — terms grouped by what moves (rates,
//! accelerations, functions of the coordinates), each group's constant factor factored —
//! in three styles: Unicode (`½ (M + m) Ẋ²`), LaTeX, and the project's own expression language
//! (which the parser reads back).

use super::algebra::{Atom, Monomial, Poly, Rational, Symbol};
use crate::expr::Function;
use std::collections::BTreeMap;

/// How to write.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// `½ (M + m) Ẋ² + m r Ẋ θ̇ cos θ`
    Unicode,
    /// `\frac{1}{2} \left(M + m\right) \dot{X}^{2}`
    Latex,
    /// `(1/2)*(M + m)*X_dot^2`: the scene-file expression language.
    Plain,
}

/// How each symbol is written in each style.
#[derive(Clone, Debug)]
pub struct Names {
    /// `[unicode, latex, plain]` per symbol.
    pub names: Vec<[String; 3]>,
    /// Whether a symbol moves (coordinates, rates, accelerations, `t`, multipliers): terms are
    /// grouped by their moving part, and the constant part is factored.
    pub moving: Vec<bool>,
    /// The number of coordinates `n`: symbols `0..n` are the coordinates, `n..2n` their rates,
    /// `2n..3n` their accelerations.
    pub order: usize,
}

impl Names {
    fn name(&self, s: Symbol, style: Style) -> &str {
        &self.names[s as usize][style as usize]
    }
}

/// Greek letters spelled out in ASCII names, and their symbols.
const GREEK: [(&str, &str, &str); 24] = [
    ("alpha", "α", "\\alpha"),
    ("beta", "β", "\\beta"),
    ("gamma", "γ", "\\gamma"),
    ("delta", "δ", "\\delta"),
    ("epsilon", "ε", "\\epsilon"),
    ("zeta", "ζ", "\\zeta"),
    ("eta", "η", "\\eta"),
    ("theta", "θ", "\\theta"),
    ("kappa", "κ", "\\kappa"),
    ("lambda", "λ", "\\lambda"),
    ("mu", "μ", "\\mu"),
    ("nu", "ν", "\\nu"),
    ("xi", "ξ", "\\xi"),
    ("rho", "ρ", "\\rho"),
    ("sigma", "σ", "\\sigma"),
    ("tau", "τ", "\\tau"),
    ("phi", "φ", "\\phi"),
    ("chi", "χ", "\\chi"),
    ("psi", "ψ", "\\psi"),
    ("omega", "ω", "\\omega"),
    ("Theta", "Θ", "\\Theta"),
    ("Phi", "Φ", "\\Phi"),
    ("Psi", "Ψ", "\\Psi"),
    ("Omega", "Ω", "\\Omega"),
];

const SUBSCRIPTS: [char; 10] = ['₀', '₁', '₂', '₃', '₄', '₅', '₆', '₇', '₈', '₉'];
const SUPERSCRIPTS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];

/// A name as printed: `theta1` → (`θ₁`, `\theta_{1}`), with `dots` dots over its letter.
pub fn pretty(name: &str, dots: usize) -> (String, String) {
    // Base and subscript: trailing digits, or what follows the last `_`.
    let (base, sub) = match name.rfind('_') {
        Some(i) if i > 0 && i + 1 < name.len() => (&name[..i], &name[i + 1..]),
        _ => {
            let cut = name.trim_end_matches(|c: char| c.is_ascii_digit()).len();
            if cut == 0 || cut == name.len() { (name, "") } else { (&name[..cut], &name[cut..]) }
        }
    };
    let (base_u, base_l) = GREEK
        .iter()
        .find(|(ascii, ..)| *ascii == base)
        .map_or((base.to_string(), base.to_string()), |(_, u, l)| (u.to_string(), l.to_string()));
    let dot_u = match dots {
        1 => "\u{307}",
        2 => "\u{308}",
        _ => "",
    };
    let sub_u: String = if sub.chars().all(|c| c.is_ascii_digit()) {
        sub.chars().map(|c| SUBSCRIPTS[c as usize - '0' as usize]).collect()
    } else {
        format!("_{sub}")
    };
    let latex_base = match dots {
        1 => format!("\\dot{{{base_l}}}"),
        2 => format!("\\ddot{{{base_l}}}"),
        _ => base_l,
    };
    let latex = if sub.is_empty() { latex_base } else { format!("{latex_base}_{{{sub}}}") };
    // The dot over the first letter of a name of several (`ẋp`), over the letter itself otherwise.
    let unicode = match base_u.char_indices().nth(1) {
        Some((i, _)) if !dot_u.is_empty() => format!("{}{dot_u}{}{sub_u}", &base_u[..i], &base_u[i..]),
        _ => format!("{base_u}{dot_u}{sub_u}"),
    };
    (unicode, latex)
}

fn superscript(k: i32) -> String {
    let digits: String =
        k.unsigned_abs().to_string().chars().map(|c| SUPERSCRIPTS[c as usize - '0' as usize]).collect();
    if k < 0 { format!("⁻{digits}") } else { digits }
}

/// A coefficient written as a decimal: a float, or a long fraction whose denominator is
/// `2^a 5^b` (`9987502603949663/10¹⁶` is `0.9987502603949663`, exactly).
fn decimal(c: Rational) -> Option<String> {
    let Some((n, d)) = c.exact() else { return Some(float(c.to_f64())) };
    let digits = |v: i128| v.unsigned_abs().to_string().len();
    if d == 1 || digits(n) + digits(d) <= 8 {
        return None;
    }
    let (mut rest, mut twos, mut fives) = (d, 0_u32, 0_u32);
    while rest % 2 == 0 {
        rest /= 2;
        twos += 1;
    }
    while rest % 5 == 0 {
        rest /= 5;
        fives += 1;
    }
    if rest != 1 {
        return None;
    }
    let k = twos.max(fives);
    let scaled = n.checked_mul(2_i128.checked_pow(k - twos)?)?.checked_mul(5_i128.checked_pow(k - fives)?)?;
    let body = format!("{:0>width$}", scaled.unsigned_abs(), width = k as usize + 1);
    let (int, frac) = body.split_at(body.len() - k as usize);
    let sign = if n < 0 { "-" } else { "" };
    Some(format!("{sign}{int}.{}", frac.trim_end_matches('0')))
}

/// The coefficient in front of a product (`None` for 1); a float or a long decimal fraction as
/// a decimal.
fn coefficient(c: Rational, style: Style) -> Option<String> {
    if let Some(text) = decimal(c) {
        return Some(text);
    }
    let Some((n, d)) = c.exact() else { return Some(float(c.to_f64())) };
    match (n, d, style) {
        (1, 1, _) => None,
        (1, 2, Style::Unicode) => Some("½".into()),
        (1, 3, Style::Unicode) => Some("⅓".into()),
        (1, 4, Style::Unicode) => Some("¼".into()),
        (2, 3, Style::Unicode) => Some("⅔".into()),
        (3, 4, Style::Unicode) => Some("¾".into()),
        (_, 1, _) => Some(n.to_string()),
        (_, _, Style::Latex) => Some(format!("\\frac{{{n}}}{{{d}}}")),
        (_, _, Style::Plain) => Some(format!("({n}/{d})")),
        (_, _, Style::Unicode) => Some(format!("{n}/{d}")),
    }
}

/// A float coefficient: the shortest decimal that reads back to it (`1e-20`, not twenty zeros).
fn float(v: f64) -> String {
    let text = format!("{v:?}");
    if text.contains('e') || text.len() <= 20 { text } else { format!("{v:e}") }
}

/// Write `p`, grouped and factored.
pub fn write(p: &Poly, names: &Names, style: Style) -> String {
    if p.is_zero() {
        return "0".into();
    }
    // Group by the moving part of each monomial.
    let mut groups: BTreeMap<Monomial, Poly> = BTreeMap::new();
    for (m, &c) in &p.0 {
        let (moving, fixed): (Monomial, Monomial) =
            m.iter().map(|(a, &e)| (a.clone(), e)).partition(|(a, _)| moves(a, names));
        let group = groups.entry(moving).or_default();
        *group = group.add(&Poly(BTreeMap::from([(fixed, c)]))).unwrap_or_else(|_| group.clone());
    }
    // As a textbook orders them: the highest derivatives first, then by the powers of the
    // symbols in their order (coordinates, rates, accelerations, …), larger first.
    let mut ordered: Vec<(&Monomial, &Poly)> = groups.iter().collect();
    let exponents = |m: &Monomial| -> Vec<i32> {
        let mut v = vec![0; names.names.len()];
        for (a, &e) in m {
            if let Atom::Sym(s) = a {
                v[*s as usize] = e;
            }
        }
        v
    };
    let n = names.order;
    ordered.sort_by_key(|(m, _)| {
        let v = exponents(m);
        let degree = |range: std::ops::Range<usize>| -> i32 { v[range].iter().sum() };
        let mut key = vec![-degree(2 * n..3 * n), -degree(n..2 * n)];
        key.extend(v[2 * n..3 * n].iter().chain(&v[n..2 * n]).chain(&v[..n]).map(|e| -e));
        key
    });
    let mut out = String::new();
    for (i, (key, coefficient_poly)) in ordered.into_iter().enumerate() {
        let (negative, text) = group(coefficient_poly, key, names, style);
        out.push_str(sign(i, negative, style));
        out.push_str(&text);
    }
    out
}

fn moves(a: &Atom, names: &Names) -> bool {
    match a {
        Atom::Sym(s) => names.moving[*s as usize],
        Atom::Fun(_, p) | Atom::Pow(p, _) => p.contains(&|s| names.moving[s as usize]),
        Atom::Atan2(y, x) => y.contains(&|s| names.moving[s as usize]) || x.contains(&|s| names.moving[s as usize]),
    }
}

/// One group `c · (sum) · common · key`, with its sign apart.
fn group(coefficient_poly: &Poly, key: &Monomial, names: &Names, style: Style) -> (bool, String) {
    let (content, common, rest) = factor(coefficient_poly);
    let negative = content.is_negative();
    let content = if negative { -content } else { content };
    let mut numerator: Vec<String> = Vec::new();
    let mut denominator: Vec<String> = Vec::new();
    let fraction = coefficient(content, style);
    match content.exact().filter(|_| decimal(content).is_none()) {
        // ½, ⅓, … in Unicode and \frac{n}{d} in LaTeX stand in front; otherwise n above, d below.
        Some((n, d)) => {
            let special = (style == Style::Unicode
                && fraction
                    .as_deref()
                    .is_some_and(|f| f.chars().count() == 1 && !f.chars().all(|c| c.is_ascii_digit())))
                || (style == Style::Latex && d != 1);
            if special {
                numerator.push(fraction.unwrap_or_default());
            } else {
                if n != 1 {
                    numerator.push(n.to_string());
                }
                if d != 1 {
                    denominator.push(d.to_string());
                }
            }
        }
        None => numerator.extend(fraction),
    }
    if rest.0.len() > 1 {
        numerator.push(paren(&terms(&rest, names, style), style));
    } else if let Some((m, c)) = rest.0.iter().next() {
        // A single remaining term (content 1 after factoring): its own atoms.
        debug_assert!(*c == Rational::int(1) || c.exact().is_none());
        factors(m, names, style, &mut numerator, &mut denominator);
    }
    factors(&common, names, style, &mut numerator, &mut denominator);
    factors(key, names, style, &mut numerator, &mut denominator);
    (negative, join(numerator, denominator, style))
}

/// The sign that joins term `i` of a sum: none before a positive first term.
fn sign(i: usize, negative: bool, style: Style) -> &'static str {
    match (i, negative, style) {
        (0, true, Style::Unicode) => "−",
        (0, true, _) => "-",
        (0, false, _) => "",
        (_, true, Style::Unicode) => " − ",
        (_, true, _) => " - ",
        (_, false, _) => " + ",
    }
}

/// `p` term by term, ungrouped (a factored group's sum, a function's argument).
fn terms(p: &Poly, names: &Names, style: Style) -> String {
    if p.is_zero() {
        return "0".into();
    }
    let mut out = String::new();
    for (i, (m, &c)) in p.0.iter().enumerate() {
        let negative = c.is_negative();
        let magnitude = if negative { -c } else { c };
        let (mut numerator, mut denominator) = (Vec::new(), Vec::new());
        match (coefficient(magnitude, style), magnitude.exact().filter(|_| decimal(magnitude).is_none())) {
            (Some(_), Some((n, d)))
                if d != 1 && style == Style::Unicode && !(n == 1 && d <= 4) && (n, d) != (2, 3) && (n, d) != (3, 4) =>
            {
                numerator.push(n.to_string());
                denominator.push(d.to_string());
            }
            (Some(text), _) => numerator.push(text),
            (None, _) => {}
        }
        factors(m, names, style, &mut numerator, &mut denominator);
        out.push_str(sign(i, negative, style));
        out.push_str(&join(numerator, denominator, style));
    }
    out
}

fn paren(text: &str, style: Style) -> String {
    match style {
        Style::Latex => format!("\\left({text}\\right)"),
        _ => format!("({text})"),
    }
}

fn join(numerator: Vec<String>, denominator: Vec<String>, style: Style) -> String {
    let sep = match style {
        Style::Plain => "*",
        Style::Latex | Style::Unicode => " ",
    };
    let num = if numerator.is_empty() { "1".to_string() } else { numerator.join(sep) };
    if denominator.is_empty() {
        return num;
    }
    let den = denominator.join(sep);
    match style {
        Style::Latex => format!("\\frac{{{num}}}{{{den}}}"),
        Style::Plain => format!("{num}/({den})"),
        Style::Unicode => {
            let den = if denominator.len() > 1 { format!("({den})") } else { den };
            format!("{num}/{den}")
        }
    }
}

/// The factors of a monomial, each with its power, sorted into numerator and denominator.
fn factors(m: &Monomial, names: &Names, style: Style, numerator: &mut Vec<String>, denominator: &mut Vec<String>) {
    for (atom, &e) in m {
        let (text, e) = match atom {
            // A power of a sum to a negative rational power goes below as a positive one.
            Atom::Pow(p, r) if r.is_negative() => {
                let text = if -*r == Rational::int(1) {
                    paren(&terms(p, names, style), style)
                } else {
                    atom_text(&Atom::Pow(p.clone(), -*r), names, style)
                };
                (text, -e)
            }
            _ => (atom_text(atom, names, style), e),
        };
        let target = if e < 0 { &mut *denominator } else { &mut *numerator };
        target.push(power(&text, e.abs(), atom, style));
    }
}

fn power(text: &str, e: i32, atom: &Atom, style: Style) -> String {
    if e == 1 {
        return text.to_string();
    }
    match (style, atom) {
        // sin²θ, as textbooks write it: the power on the function's name.
        (Style::Unicode, Atom::Fun(f, _)) if text.starts_with(f.name()) => {
            format!("{}{}{}", f.name(), superscript(e), &text[f.name().len()..])
        }
        (Style::Unicode, _) => format!("{text}{}", superscript(e)),
        (Style::Latex, _) => format!("{{{text}}}^{{{e}}}"),
        (Style::Plain, _) => format!("{text}^{e}"),
    }
}

fn atom_text(atom: &Atom, names: &Names, style: Style) -> String {
    match atom {
        Atom::Sym(s) => names.name(*s, style).to_string(),
        Atom::Fun(f, p) => {
            let inner = terms(p, names, style);
            let simple = p.0.len() == 1
                && p.0.iter().next().is_some_and(|(m, c)| {
                    *c == Rational::int(1)
                        && m.len() == 1
                        && m.values().all(|&e| e == 1)
                        && m.keys().all(|a| matches!(a, Atom::Sym(_)))
                });
            match style {
                Style::Unicode if simple => format!("{} {inner}", f.name()),
                Style::Unicode => format!("{}({inner})", f.name()),
                Style::Latex => {
                    let name = match f {
                        Function::Sin
                        | Function::Cos
                        | Function::Tan
                        | Function::Sinh
                        | Function::Cosh
                        | Function::Exp
                        | Function::Ln => {
                            format!("\\{}", f.name())
                        }
                        Function::Sqrt => return format!("\\sqrt{{{inner}}}"),
                        other => format!("\\operatorname{{{}}}", other.name()),
                    };
                    if simple { format!("{name} {inner}") } else { format!("{name}\\left({inner}\\right)") }
                }
                Style::Plain => format!("{}({inner})", f.name()),
            }
        }
        Atom::Atan2(y, x) => {
            let (y, x) = (terms(y, names, style), terms(x, names, style));
            match style {
                Style::Latex => format!("\\operatorname{{atan2}}\\left({y}, {x}\\right)"),
                _ => format!("atan2({y}, {x})"),
            }
        }
        Atom::Pow(p, r) => {
            let inner = terms(p, names, style);
            let half = *r == Rational::new(1, 2).unwrap_or(Rational::int(0));
            match style {
                Style::Unicode if half => format!("√({inner})"),
                Style::Latex if half => format!("\\sqrt{{{inner}}}"),
                _ => match (r.exact(), style) {
                    (Some((1, 1)), _) => paren(&inner, style),
                    (Some((n, 1)), Style::Unicode) => format!("({inner}){}", superscript(n as i32)),
                    (Some((n, 1)), Style::Plain) => format!("({inner})^{n}"),
                    (Some((n, 1)), Style::Latex) => format!("\\left({inner}\\right)^{{{n}}}"),
                    (Some((n, d)), Style::Unicode | Style::Plain) => format!("({inner})^({n}/{d})"),
                    (Some((n, d)), Style::Latex) => format!("\\left({inner}\\right)^{{{n}/{d}}}"),
                    (None, Style::Latex) => format!("\\left({inner}\\right)^{{{}}}", float(r.to_f64())),
                    (None, _) => format!("({inner})^({})", float(r.to_f64())),
                },
            }
        }
    }
}

/// `p = content · common · rest`: the rational content (sign of the first term), the atoms every
/// term has (least power), and what remains.
fn factor(p: &Poly) -> (Rational, Monomial, Poly) {
    let mut terms = p.0.iter();
    let Some((first, &c0)) = terms.next() else { return (Rational::int(0), Monomial::new(), Poly::zero()) };
    let mut common: Monomial = first.clone();
    let mut content = c0.exact().map(|(n, d)| (n.abs(), d));
    for (m, &c) in terms {
        common = common
            .iter()
            .filter_map(|(a, &e)| {
                let f = *m.get(a)?;
                if f.signum() != e.signum() {
                    return None;
                }
                Some((a.clone(), if e > 0 { e.min(f) } else { e.max(f) }))
            })
            .collect();
        content = match (content, c.exact()) {
            (Some((num, den)), Some((n, d))) => Some((gcd(num, n.abs()), lcm(den, d))),
            _ => None,
        };
    }
    let sign = if c0.is_negative() { -1 } else { 1 };
    // Floats share no content; a lone float term is its own.
    let content = match content {
        Some((num, den)) => Rational::new(sign * num, den).unwrap_or(Rational::int(1)),
        None if p.0.len() == 1 => c0,
        None => Rational::int(sign),
    };
    let inverse = Poly(BTreeMap::from([(
        common.iter().map(|(a, &e)| (a.clone(), -e)).collect(),
        content.recip().unwrap_or(Rational::int(1)),
    )]));
    let rest = p.mul(&inverse).unwrap_or_else(|_| p.clone());
    (content, common, rest)
}

fn gcd(a: i128, b: i128) -> i128 {
    let (mut a, mut b) = (a, b);
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a.max(1)
}

fn lcm(a: i128, b: i128) -> i128 {
    (a / gcd(a, b)).saturating_mul(b)
}
