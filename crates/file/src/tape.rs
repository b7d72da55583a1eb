//! Expressions compiled once into a tape: a list of operations in evaluation order, each
//! operation stored once however often it occurs (hash-consed, so `sin(θ)` in three bodies is
//! one operation), constants folded, and evaluated over any [`Scalar`] of the engine into a
//! caller's buffer without allocating.

use crate::expr::{Ast, BinaryOp, Function, Span};
use lagrange::Scalar;
use std::collections::HashMap;

/// What a name stands for when an expression is compiled.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Leaf {
    /// A value known when the tape is built (a parameter, `pi`).
    Constant(f64),
    /// The `k`-th entry of the inputs the tape is evaluated at.
    Input(usize),
}

/// One operation of a tape; operands are indices of earlier operations.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Op {
    /// A constant, by its bits (so that operations hash).
    Constant(u64),
    Input(u32),
    Neg(u32),
    Add(u32, u32),
    Sub(u32, u32),
    Mul(u32, u32),
    Div(u32, u32),
    PowI(u32, i32),
    /// `a^c` for a constant non-integer `c`, by its bits.
    PowF(u32, u64),
    /// `a^b` for a variable exponent.
    Pow(u32, u32),
    Call(Function, u32),
    Atan2(u32, u32),
    /// `sin a` here and `cos a` into slot `c` (later), from one `sin_cos`: a tape holding both
    /// computes the trigonometry once, as hand-written code does.
    SinCos(u32, u32),
    /// `cos a` here and `sin a` into slot `c` (later).
    CosSin(u32, u32),
    /// A slot an earlier `SinCos` or `CosSin` filled.
    Filled,
}

/// A node of a tape being built: the index of its operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Node(u32);

/// Builds a [`Tape`] from expressions, sharing every repeated subexpression.
#[derive(Debug, Default)]
pub struct TapeBuilder {
    ops: Vec<Op>,
    index: HashMap<Op, u32>,
    outputs: Vec<u32>,
}

/// The largest integer exponent written as repeated multiplication (`powi`) rather than
/// `exp(c ln a)`: beyond it the integer power's rounding is no better.
const MAX_INTEGER_POWER: f64 = 64.0;

impl TapeBuilder {
    /// An empty builder.
    pub fn new() -> Self {
        Self::default()
    }

    fn push(&mut self, op: Op) -> Node {
        if let Some(&i) = self.index.get(&op) {
            return Node(i);
        }
        let i = u32::try_from(self.ops.len()).expect("fewer than 2^32 operations");
        self.ops.push(op);
        self.index.insert(op, i);
        Node(i)
    }

    /// A constant node.
    pub fn constant(&mut self, value: f64) -> Node {
        // -0.0 and 0.0 are one constant.
        let value = if value == 0.0 { 0.0 } else { value };
        self.push(Op::Constant(value.to_bits()))
    }

    /// An input node.
    pub fn input(&mut self, k: usize) -> Node {
        self.push(Op::Input(u32::try_from(k).expect("fewer than 2^32 inputs")))
    }

    /// The value of `node` if it is a constant.
    pub fn value(&self, node: Node) -> Option<f64> {
        match self.ops[node.0 as usize] {
            Op::Constant(bits) => Some(f64::from_bits(bits)),
            _ => None,
        }
    }

    /// `−a`
    pub fn neg(&mut self, a: Node) -> Node {
        match self.ops[a.0 as usize] {
            Op::Constant(bits) => self.constant(-f64::from_bits(bits)),
            Op::Neg(inner) => Node(inner),
            _ => self.push(Op::Neg(a.0)),
        }
    }

    /// `a op b`, folded where both are constants or one is a neutral element.
    pub fn binary(&mut self, op: BinaryOp, a: Node, b: Node) -> Node {
        let (va, vb) = (self.value(a), self.value(b));
        if let (Some(x), Some(y)) = (va, vb) {
            let folded = match op {
                BinaryOp::Add => x + y,
                BinaryOp::Sub => x - y,
                BinaryOp::Mul => x * y,
                BinaryOp::Div => x / y,
                BinaryOp::Pow => x.powf(y),
            };
            if folded.is_finite() {
                return self.constant(folded);
            }
        }
        // Commutative operations in one operand order, so that a*b and b*a are one node.
        let ordered = |a: Node, b: Node| if a.0 <= b.0 { (a.0, b.0) } else { (b.0, a.0) };
        match op {
            BinaryOp::Add if va == Some(0.0) => b,
            BinaryOp::Add | BinaryOp::Sub if vb == Some(0.0) => a,
            BinaryOp::Add => {
                let (x, y) = ordered(a, b);
                self.push(Op::Add(x, y))
            }
            BinaryOp::Sub if va == Some(0.0) => self.neg(b),
            BinaryOp::Sub if a == b => self.constant(0.0),
            BinaryOp::Sub => self.push(Op::Sub(a.0, b.0)),
            BinaryOp::Mul if va == Some(0.0) || vb == Some(0.0) => self.constant(0.0),
            BinaryOp::Mul if va == Some(1.0) => b,
            BinaryOp::Mul if vb == Some(1.0) => a,
            BinaryOp::Mul if va == Some(-1.0) => self.neg(b),
            BinaryOp::Mul if vb == Some(-1.0) => self.neg(a),
            BinaryOp::Mul => {
                let (x, y) = ordered(a, b);
                self.push(Op::Mul(x, y))
            }
            BinaryOp::Div if vb == Some(1.0) => a,
            BinaryOp::Div if va == Some(0.0) => self.constant(0.0),
            BinaryOp::Div => self.push(Op::Div(a.0, b.0)),
            BinaryOp::Pow => self.power(a, b, vb),
        }
    }

    fn power(&mut self, a: Node, b: Node, exponent: Option<f64>) -> Node {
        match exponent {
            Some(0.0) => self.constant(1.0),
            Some(1.0) => a,
            Some(0.5) => self.call(Function::Sqrt, &[a]),
            Some(c) if c.fract() == 0.0 && c.abs() <= MAX_INTEGER_POWER => self.push(Op::PowI(a.0, c as i32)),
            Some(c) => self.push(Op::PowF(a.0, c.to_bits())),
            None => self.push(Op::Pow(a.0, b.0)),
        }
    }

    /// `f(args)`, folded where the arguments are constants.
    pub fn call(&mut self, function: Function, args: &[Node]) -> Node {
        if let Some(values) = args.iter().map(|&a| self.value(a)).collect::<Option<Vec<f64>>>() {
            let folded = evaluate_call(function, values[0], values.get(1).copied().unwrap_or(0.0));
            if folded.is_finite() {
                return self.constant(folded);
            }
        }
        match function {
            Function::Atan2 => self.push(Op::Atan2(args[0].0, args[1].0)),
            f => self.push(Op::Call(f, args[0].0)),
        }
    }

    /// Compile `ast`, reading each name through `resolve` (which says what the name stands
    /// for, or gives the caller's error for a name that is not allowed there).
    ///
    /// # Errors
    /// The first error `resolve` returns.
    pub fn compile<E>(
        &mut self,
        ast: &Ast,
        resolve: &mut impl FnMut(&str, &Span) -> Result<Leaf, E>,
    ) -> Result<Node, E> {
        Ok(match ast {
            Ast::Number(v, _) => self.constant(*v),
            Ast::Name(name, span) => match resolve(name, span)? {
                Leaf::Constant(v) => self.constant(v),
                Leaf::Input(k) => self.input(k),
            },
            Ast::Neg(a, _) => {
                let a = self.compile(a, resolve)?;
                self.neg(a)
            }
            Ast::Binary(op, a, b, _) => {
                let a = self.compile(a, resolve)?;
                let b = self.compile(b, resolve)?;
                self.binary(*op, a, b)
            }
            Ast::Call(function, args, _) => {
                let mut nodes = [Node(0); 2];
                for (slot, arg) in nodes.iter_mut().zip(args) {
                    *slot = self.compile(arg, resolve)?;
                }
                self.call(*function, &nodes[..args.len()])
            }
        })
    }

    /// Make `node` the next output of the tape.
    pub fn output(&mut self, node: Node) {
        self.outputs.push(node.0);
    }

    /// The tape: the operations the outputs need, in evaluation order.
    pub fn finish(self) -> Tape {
        // Keep only what an output reaches (folding leaves constants nothing uses).
        let mut live = vec![false; self.ops.len()];
        for &o in &self.outputs {
            live[o as usize] = true;
        }
        for i in (0..self.ops.len()).rev() {
            if live[i] {
                for operand in operands(self.ops[i]) {
                    live[operand as usize] = true;
                }
            }
        }
        let mut renumber = vec![u32::MAX; self.ops.len()];
        let mut ops = Vec::new();
        for (i, op) in self.ops.iter().enumerate() {
            if live[i] {
                renumber[i] = ops.len() as u32;
                ops.push(map_operands(*op, |k| renumber[k as usize]));
            }
        }
        let outputs = self.outputs.iter().map(|&o| renumber[o as usize]).collect();
        Tape { ops: fuse_sin_cos(ops), outputs }
    }
}

/// Where a tape computes both `sin a` and `cos a`, compute them together at the first of the
/// two slots and mark the second filled.
fn fuse_sin_cos(mut ops: Vec<Op>) -> Vec<Op> {
    let mut first: HashMap<(u32, bool), u32> = HashMap::new();
    for (i, op) in ops.iter().enumerate() {
        if let Op::Call(f @ (Function::Sin | Function::Cos), a) = *op {
            first.entry((a, f == Function::Sin)).or_insert(i as u32);
        }
    }
    for (&(a, is_sin), &i) in &first {
        if !is_sin {
            continue;
        }
        if let Some(&j) = first.get(&(a, false)) {
            let (at, other) = (i.min(j), i.max(j));
            // The op at `at` is the one listed first: it keeps its own value and fills the other.
            if i < j {
                ops[at as usize] = Op::SinCos(a, other);
            } else {
                ops[at as usize] = Op::CosSin(a, other);
            }
            ops[other as usize] = Op::Filled;
        }
    }
    ops
}

fn operands(op: Op) -> impl Iterator<Item = u32> {
    let (a, b) = match op {
        Op::Constant(_) | Op::Input(_) | Op::Filled => (None, None),
        Op::Neg(a) | Op::PowI(a, _) | Op::PowF(a, _) | Op::Call(_, a) | Op::SinCos(a, _) | Op::CosSin(a, _) => {
            (Some(a), None)
        }
        Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) | Op::Div(a, b) | Op::Pow(a, b) | Op::Atan2(a, b) => {
            (Some(a), Some(b))
        }
    };
    a.into_iter().chain(b)
}

fn map_operands(op: Op, f: impl Fn(u32) -> u32) -> Op {
    match op {
        Op::Constant(_) | Op::Input(_) | Op::Filled => op,
        Op::SinCos(a, c) => Op::SinCos(f(a), f(c)),
        Op::CosSin(a, c) => Op::CosSin(f(a), f(c)),
        Op::Neg(a) => Op::Neg(f(a)),
        Op::PowI(a, n) => Op::PowI(f(a), n),
        Op::PowF(a, c) => Op::PowF(f(a), c),
        Op::Call(g, a) => Op::Call(g, f(a)),
        Op::Add(a, b) => Op::Add(f(a), f(b)),
        Op::Sub(a, b) => Op::Sub(f(a), f(b)),
        Op::Mul(a, b) => Op::Mul(f(a), f(b)),
        Op::Div(a, b) => Op::Div(f(a), f(b)),
        Op::Pow(a, b) => Op::Pow(f(a), f(b)),
        Op::Atan2(a, b) => Op::Atan2(f(a), f(b)),
    }
}

/// `f(x)` (`f(x, y)` for `atan2`) in f64, for folding: the same arithmetic as the tape's.
fn evaluate_call(function: Function, x: f64, y: f64) -> f64 {
    if function == Function::Atan2 { x.atan2(y) } else { apply(function, x) }
}

fn apply<S: Scalar>(function: Function, x: S) -> S {
    match function {
        Function::Sin => x.sin(),
        Function::Cos => x.cos(),
        Function::Tan => x.tan(),
        Function::Asin => x.asin(),
        Function::Acos => x.acos(),
        Function::Atan => x.atan(),
        Function::Sinh => x.sinh(),
        Function::Cosh => x.cosh(),
        Function::Exp => x.exp(),
        Function::Ln => x.ln(),
        Function::Sqrt => x.sqrt(),
        // The derivative of |x| at 0 is taken as +1 (one side), as f64::abs's sign convention.
        Function::Abs => {
            if x < 0.0 {
                -x
            } else {
                x
            }
        }
        Function::Atan2 => unreachable!("atan2 has two arguments"),
    }
}

/// Compiled expressions: operations in evaluation order and the outputs they give.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tape {
    ops: Vec<Op>,
    outputs: Vec<u32>,
}

impl Tape {
    /// The number of slots [`eval`](Self::eval) needs.
    pub fn len(&self) -> usize {
        self.ops.len()
    }

    /// Whether the tape computes nothing.
    pub fn is_empty(&self) -> bool {
        self.ops.is_empty()
    }

    /// Whether every output is the constant 0 (a force that the parameters switch off).
    pub fn is_zero(&self) -> bool {
        self.outputs.iter().all(|&o| self.ops[o as usize] == Op::Constant(0.0_f64.to_bits()))
    }

    /// The number of outputs.
    pub fn outputs(&self) -> usize {
        self.outputs.len()
    }

    /// Evaluate at `inputs`, with `slots` (at least [`len`](Self::len) long, contents
    /// overwritten) as working memory, writing output `i` to `out[i]`.
    ///
    /// # Panics
    /// If `slots` or `out` is too short, or an input index is beyond `inputs`.
    pub fn eval<S: Scalar>(&self, inputs: &[S], slots: &mut [S], out: &mut [S]) {
        for (i, op) in self.ops.iter().enumerate() {
            let s = |k: u32| slots[k as usize];
            let value = match *op {
                Op::Constant(bits) => S::from(f64::from_bits(bits)),
                Op::Input(k) => inputs[k as usize],
                Op::Neg(a) => -s(a),
                Op::Add(a, b) => s(a) + s(b),
                Op::Sub(a, b) => s(a) - s(b),
                Op::Mul(a, b) => s(a) * s(b),
                Op::Div(a, b) => s(a) / s(b),
                Op::PowI(a, n) => s(a).powi(n),
                Op::PowF(a, c) => s(a).powf(f64::from_bits(c)),
                Op::Pow(a, b) => s(a).powd(s(b)),
                Op::Call(f, a) => apply(f, s(a)),
                Op::Atan2(a, b) => s(a).atan2(s(b)),
                Op::SinCos(a, c) => {
                    let (sin, cos) = s(a).sin_cos();
                    slots[c as usize] = cos;
                    sin
                }
                Op::CosSin(a, c) => {
                    let (sin, cos) = s(a).sin_cos();
                    slots[c as usize] = sin;
                    cos
                }
                Op::Filled => continue,
            };
            slots[i] = value;
        }
        for (o, &k) in out.iter_mut().zip(&self.outputs) {
            *o = slots[k as usize];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::expr::parse;
    use lagrange::num_dual::{Dual64, DualStruct};

    fn compile(texts: &[&str]) -> Tape {
        let mut builder = TapeBuilder::new();
        for text in texts {
            let ast = parse(text).unwrap();
            let node = builder
                .compile(&ast, &mut |name: &str, _: &Span| match name {
                    "x" => Ok::<_, ()>(Leaf::Input(0)),
                    "y" => Ok(Leaf::Input(1)),
                    "k" => Ok(Leaf::Constant(2.0)),
                    "pi" => Ok(Leaf::Constant(std::f64::consts::PI)),
                    _ => Err(()),
                })
                .unwrap();
            builder.output(node);
        }
        builder.finish()
    }

    #[test]
    fn repeated_subexpressions_are_one_operation_and_constants_fold() {
        // x, y, sin(x), cos(y), sin(x)*cos(y): five operations whatever the spelling.
        let tape = compile(&["sin(x)*cos(y)", "cos(y)*sin(x) + 0", "2*k/4*sin(x)*cos(y)"]);
        assert_eq!(tape.len(), 5, "{tape:?}");
        // A constant expression is one constant.
        assert_eq!(compile(&["k^3*cos(pi) + sqrt(k*8)"]).len(), 1);
        let mut out = [0.0; 3];
        tape.eval(&[0.3, 0.7], &mut [0.0; 5], &mut out);
        let expected = 0.3_f64.sin() * 0.7_f64.cos();
        assert_eq!(out, [expected; 3]);
    }

    #[test]
    fn evaluates_every_function_and_its_derivative() {
        let texts = [
            "sin(x) + cos(x) + tan(x)",
            "asin(x) + acos(x) + atan(x)",
            "atan2(y, x)",
            "sinh(x) * cosh(x) / exp(x)",
            "ln(y) + sqrt(y) + abs(-x)",
            "x^3 + x^-2 + y^1.5 + x^y",
        ];
        let tape = compile(&texts);
        let (x, y): (f64, f64) = (0.4, 1.3);
        let expected: [(f64, f64); 6] = [
            (x.sin() + x.cos() + x.tan(), x.cos() - x.sin() + 1.0 / (x.cos() * x.cos())),
            (x.asin() + x.acos() + x.atan(), 1.0 / (1.0 + x * x)),
            (y.atan2(x), -y / (x * x + y * y)),
            (x.sinh() * x.cosh() / x.exp(), (x.cosh().powi(2) + x.sinh().powi(2) - x.sinh() * x.cosh()) / x.exp()),
            (y.ln() + y.sqrt() + x, 1.0),
            (x.powi(3) + x.powi(-2) + y.powf(1.5) + x.powf(y), 3.0 * x * x - 2.0 / x.powi(3) + y * x.powf(y - 1.0)),
        ];
        let mut slots = vec![Dual64::from(0.0); tape.len()];
        let mut out = [Dual64::from(0.0); 6];
        tape.eval(&[Dual64::new(x, 1.0), Dual64::from(y)], &mut slots, &mut out);
        for ((value, (f, df)), text) in out.iter().zip(expected).zip(texts) {
            approx::assert_relative_eq!(value.re(), f, max_relative = 1e-14);
            approx::assert_relative_eq!(value.eps, df, max_relative = 1e-13);
            let _ = text;
        }
    }
}

#[cfg(test)]
mod fusion {
    use super::*;
    use crate::expr::parse;

    #[test]
    fn sine_and_cosine_of_one_argument_are_one_sin_cos_in_either_order() {
        for texts in [["r*cos(theta)", "r*sin(theta)"], ["r*sin(theta)", "r*cos(theta)"]] {
            let mut builder = TapeBuilder::new();
            for text in texts {
                let node = builder
                    .compile(&parse(text).unwrap(), &mut |name: &str, _: &Span| {
                        Ok::<_, ()>(Leaf::Input(usize::from(name == "theta")))
                    })
                    .unwrap();
                builder.output(node);
            }
            let tape = builder.finish();
            assert_eq!(
                tape.ops.iter().filter(|op| matches!(op, Op::SinCos(..) | Op::CosSin(..))).count(),
                1,
                "{tape:?}"
            );
            let mut out = [0.0; 2];
            tape.eval(&[2.0, 0.3], &mut vec![0.0; tape.len()], &mut out);
            let expected = if texts[0].contains("cos") {
                [2.0 * 0.3_f64.cos(), 2.0 * 0.3_f64.sin()]
            } else {
                [2.0 * 0.3_f64.sin(), 2.0 * 0.3_f64.cos()]
            };
            assert_eq!(out, expected);
        }
    }
}
