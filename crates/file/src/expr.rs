//! Expressions of a scene file: the grammar, parsed into a syntax tree that keeps where each
//! part came from.
//!
//! ```text
//! expression := sum
//! sum        := product (("+" | "-") product)*
//! product    := unary (("*" | "/") unary)*
//! unary      := "-" unary | "+" unary | power
//! power      := atom ("^" unary)?            (right-associative: a^b^c = a^(b^c); -x^2 = -(x^2))
//! atom       := number | name | name "(" expression ("," expression)* ")" | "(" expression ")"
//! ```
//!
//! Numbers are decimal (`3`, `0.5`, `1e-3`, `.25`); names are letters (any alphabet: `θ`, `m₁`),
//! digits, `_` and `'`, not starting with a digit or `'`.

use std::ops::Range;

/// Byte range of a part of an expression, relative to the expression's text.
pub type Span = Range<usize>;

/// A binary operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BinaryOp {
    /// `a + b`
    Add,
    /// `a - b`
    Sub,
    /// `a * b`
    Mul,
    /// `a / b`
    Div,
    /// `a ^ b`
    Pow,
}

/// A function of the expression language.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Function {
    /// `sin x`
    Sin,
    /// `cos x`
    Cos,
    /// `tan x`
    Tan,
    /// `asin x`
    Asin,
    /// `acos x`
    Acos,
    /// `atan x`
    Atan,
    /// `atan2(y, x)`, the angle of the point `(x, y)`.
    Atan2,
    /// `sinh x`
    Sinh,
    /// `cosh x`
    Cosh,
    /// `exp x`
    Exp,
    /// `ln x`
    Ln,
    /// `sqrt x`
    Sqrt,
    /// `abs x`
    Abs,
}

impl Function {
    /// Every function, with the name it is called by.
    pub const ALL: [(Function, &'static str); 13] = [
        (Function::Sin, "sin"),
        (Function::Cos, "cos"),
        (Function::Tan, "tan"),
        (Function::Asin, "asin"),
        (Function::Acos, "acos"),
        (Function::Atan, "atan"),
        (Function::Atan2, "atan2"),
        (Function::Sinh, "sinh"),
        (Function::Cosh, "cosh"),
        (Function::Exp, "exp"),
        (Function::Ln, "ln"),
        (Function::Sqrt, "sqrt"),
        (Function::Abs, "abs"),
    ];

    /// The function called `name`.
    pub fn named(name: &str) -> Option<Function> {
        Self::ALL.iter().find(|(_, n)| *n == name).map(|(f, _)| *f)
    }

    /// Its name in an expression.
    pub fn name(self) -> &'static str {
        Self::ALL.iter().find(|(f, _)| *f == self).map(|(_, n)| *n).unwrap_or("?")
    }

    /// How many arguments it takes.
    pub fn arity(self) -> usize {
        if self == Function::Atan2 { 2 } else { 1 }
    }
}

/// A parsed expression: each node with the span of text it was read from.
#[derive(Clone, Debug, PartialEq)]
pub enum Ast {
    /// A number.
    Number(f64, Span),
    /// A name: a parameter, a coordinate, its rate, `t` or `pi`.
    Name(String, Span),
    /// `-a`
    Neg(Box<Ast>, Span),
    /// `a op b`
    Binary(BinaryOp, Box<Ast>, Box<Ast>, Span),
    /// `f(a, …)`
    Call(Function, Vec<Ast>, Span),
}

impl Ast {
    /// The span of text the node was read from.
    pub fn span(&self) -> Span {
        match self {
            Ast::Number(_, s) | Ast::Name(_, s) | Ast::Neg(_, s) | Ast::Binary(_, _, _, s) | Ast::Call(_, _, s) => {
                s.clone()
            }
        }
    }

    /// Call `visit` on every name in the expression, with its span.
    pub fn names<'a>(&'a self, visit: &mut impl FnMut(&'a str, Span)) {
        match self {
            Ast::Number(..) => {}
            Ast::Name(name, span) => visit(name, span.clone()),
            Ast::Neg(a, _) => a.names(visit),
            Ast::Binary(_, a, b, _) => {
                a.names(visit);
                b.names(visit);
            }
            Ast::Call(_, args, _) => args.iter().for_each(|a| a.names(visit)),
        }
    }
}

/// A syntax error: what is wrong, where, and what would be right.
#[derive(Clone, Debug, PartialEq)]
pub struct SyntaxError {
    /// What is wrong.
    pub message: String,
    /// Where, in the expression's text.
    pub span: Span,
    /// A hint, where one helps.
    pub hint: Option<String>,
}

#[derive(Clone, Debug, PartialEq)]
enum Token {
    Number(f64),
    Name(String),
    Op(char),
    End,
}

struct Lexer<'a> {
    text: &'a str,
    tokens: Vec<(Token, Span)>,
}

fn is_name_start(c: char) -> bool {
    c.is_alphabetic() || c == '_'
}

fn is_name_char(c: char) -> bool {
    // Subscript and superscript digits (m₁, x²) read as parts of a name.
    c.is_alphanumeric() || c == '_' || c == '\'' || ('\u{2080}'..='\u{2089}').contains(&c)
}

impl<'a> Lexer<'a> {
    fn run(text: &'a str) -> Result<Vec<(Token, Span)>, SyntaxError> {
        let mut lexer = Lexer { text, tokens: Vec::new() };
        let mut chars = text.char_indices().peekable();
        while let Some(&(start, c)) = chars.peek() {
            if c.is_whitespace() {
                chars.next();
            } else if c.is_ascii_digit() || c == '.' {
                let end = lexer.number_end(start);
                let literal = &text[start..end];
                let value: f64 = literal.parse().map_err(|_| SyntaxError {
                    message: format!("`{literal}` is not a number"),
                    span: start..end,
                    hint: Some("write numbers as 2, 0.5, .25 or 1e-3".into()),
                })?;
                if !value.is_finite() {
                    return Err(SyntaxError {
                        message: format!("`{literal}` is beyond the range of a 64-bit float (±1.8e308)"),
                        span: start..end,
                        hint: None,
                    });
                }
                lexer.tokens.push((Token::Number(value), start..end));
                while chars.peek().is_some_and(|&(i, _)| i < end) {
                    chars.next();
                }
            } else if is_name_start(c) {
                let mut end = start;
                while let Some(&(i, c)) = chars.peek() {
                    if !is_name_char(c) {
                        break;
                    }
                    end = i + c.len_utf8();
                    chars.next();
                }
                lexer.tokens.push((Token::Name(text[start..end].to_string()), start..end));
            } else if "+-*/^(),".contains(c) {
                lexer.tokens.push((Token::Op(c), start..start + 1));
                chars.next();
            } else {
                let end = start + c.len_utf8();
                let hint = match c {
                    '−' => Some("write the minus sign as `-`".to_string()),
                    '×' | '·' => Some("write multiplication as `*`".to_string()),
                    '÷' => Some("write division as `/`".to_string()),
                    '*' | '[' | ']' | '{' | '}' => Some("group with `(` and `)`".to_string()),
                    'π' => Some("write π as `pi`".to_string()),
                    _ => None,
                };
                return Err(SyntaxError { message: format!("unexpected character `{c}`"), span: start..end, hint });
            }
        }
        lexer.tokens.push((Token::End, text.len()..text.len()));
        Ok(lexer.tokens)
    }

    /// End of the number literal starting at `start`: digits, one point, an exponent.
    fn number_end(&self, start: usize) -> usize {
        let bytes = self.text.as_bytes();
        let mut i = start;
        while i < bytes.len() && (bytes[i].is_ascii_digit() || bytes[i] == b'.') {
            i += 1;
        }
        if i < bytes.len() && (bytes[i] == b'e' || bytes[i] == b'E') {
            let mut j = i + 1;
            if j < bytes.len() && (bytes[j] == b'+' || bytes[j] == b'-') {
                j += 1;
            }
            if j < bytes.len() && bytes[j].is_ascii_digit() {
                while j < bytes.len() && bytes[j].is_ascii_digit() {
                    j += 1;
                }
                i = j;
            }
        }
        i
    }
}

struct Parser {
    tokens: Vec<(Token, Span)>,
    at: usize,
}

/// Parse `text` into a syntax tree.
///
/// # Errors
/// A [`SyntaxError`] at the first part that does not fit the grammar.
pub fn parse(text: &str) -> Result<Ast, SyntaxError> {
    let tokens = Lexer::run(text)?;
    if tokens.len() == 1 {
        return Err(SyntaxError {
            message: "empty expression".into(),
            span: 0..text.len(),
            hint: Some("write 0 for zero".into()),
        });
    }
    let mut parser = Parser { tokens, at: 0 };
    let ast = parser.sum()?;
    match parser.peek() {
        (Token::End, _) => Ok(ast),
        (Token::Op(')'), span) => Err(SyntaxError { message: "unmatched `)`".into(), span: span.clone(), hint: None }),
        (token, span) => Err(SyntaxError {
            message: format!("expected an operator, found {}", describe(token)),
            span: span.clone(),
            hint: matches!(token, Token::Name(_) | Token::Number(_) | Token::Op('('))
                .then(|| "products are written with `*` (2*x, not 2x)".to_string()),
        }),
    }
}

fn describe(token: &Token) -> String {
    match token {
        Token::Number(v) => format!("the number {v}"),
        Token::Name(n) => format!("`{n}`"),
        Token::Op(c) => format!("`{c}`"),
        Token::End => "the end of the expression".into(),
    }
}

fn join(a: &Span, b: &Span) -> Span {
    a.start.min(b.start)..a.end.max(b.end)
}

impl Parser {
    fn peek(&self) -> &(Token, Span) {
        &self.tokens[self.at]
    }

    fn next(&mut self) -> (Token, Span) {
        let token = self.tokens[self.at].clone();
        if self.at + 1 < self.tokens.len() {
            self.at += 1;
        }
        token
    }

    fn eat(&mut self, op: char) -> bool {
        if self.peek().0 == Token::Op(op) {
            self.next();
            true
        } else {
            false
        }
    }

    fn sum(&mut self) -> Result<Ast, SyntaxError> {
        let mut left = self.product()?;
        loop {
            let op = match self.peek().0 {
                Token::Op('+') => BinaryOp::Add,
                Token::Op('-') => BinaryOp::Sub,
                _ => return Ok(left),
            };
            self.next();
            let right = self.product()?;
            let span = join(&left.span(), &right.span());
            left = Ast::Binary(op, Box::new(left), Box::new(right), span);
        }
    }

    fn product(&mut self) -> Result<Ast, SyntaxError> {
        let mut left = self.unary()?;
        loop {
            let op = match self.peek().0 {
                Token::Op('*') => BinaryOp::Mul,
                Token::Op('/') => BinaryOp::Div,
                _ => return Ok(left),
            };
            self.next();
            let right = self.unary()?;
            let span = join(&left.span(), &right.span());
            left = Ast::Binary(op, Box::new(left), Box::new(right), span);
        }
    }

    fn unary(&mut self) -> Result<Ast, SyntaxError> {
        let (token, span) = self.peek().clone();
        match token {
            Token::Op('-') => {
                self.next();
                let operand = self.unary()?;
                let span = join(&span, &operand.span());
                Ok(Ast::Neg(Box::new(operand), span))
            }
            Token::Op('+') => {
                self.next();
                self.unary()
            }
            _ => self.power(),
        }
    }

    fn power(&mut self) -> Result<Ast, SyntaxError> {
        let base = self.atom()?;
        if self.eat('^') {
            let exponent = self.unary()?;
            let span = join(&base.span(), &exponent.span());
            return Ok(Ast::Binary(BinaryOp::Pow, Box::new(base), Box::new(exponent), span));
        }
        Ok(base)
    }

    fn atom(&mut self) -> Result<Ast, SyntaxError> {
        let (token, span) = self.next();
        match token {
            Token::Number(v) => Ok(Ast::Number(v, span)),
            Token::Name(name) => {
                if self.peek().0 == Token::Op('(') {
                    self.call(name, span)
                } else if let Some(function) = Function::named(&name) {
                    Err(SyntaxError {
                        message: format!("`{name}` is a function and takes its argument in parentheses"),
                        span,
                        hint: Some(format!(
                            "write {name}(x){}",
                            if function.arity() == 2 { " with two arguments" } else { "" }
                        )),
                    })
                } else {
                    Ok(Ast::Name(name, span))
                }
            }
            Token::Op('(') => {
                let inner = self.sum()?;
                let (close, close_span) = self.next();
                if close != Token::Op(')') {
                    return Err(SyntaxError {
                        message: format!("expected `)`, found {}", describe(&close)),
                        span: close_span,
                        hint: Some(format!("the `(` at byte {} is not closed", span.start)),
                    });
                }
                Ok(inner)
            }
            token => Err(SyntaxError {
                message: format!("expected a number, a name or `(`, found {}", describe(&token)),
                span,
                hint: None,
            }),
        }
    }

    fn call(&mut self, name: String, name_span: Span) -> Result<Ast, SyntaxError> {
        let Some(function) = Function::named(&name) else {
            let hint = crate::names::suggest(&name, Function::ALL.iter().map(|(_, n)| *n))
                .map(|s| format!("did you mean `{s}`?"))
                .or_else(|| Some("products are written with `*`: a*(b + c)".into()));
            return Err(SyntaxError { message: format!("unknown function `{name}`"), span: name_span, hint });
        };
        self.next(); // (
        let mut args = vec![self.sum()?];
        while self.eat(',') {
            args.push(self.sum()?);
        }
        let (close, close_span) = self.next();
        if close != Token::Op(')') {
            return Err(SyntaxError {
                message: format!("expected `,` or `)` in the call of `{name}`, found {}", describe(&close)),
                span: close_span,
                hint: None,
            });
        }
        let span = name_span.start..close_span.end;
        if args.len() != function.arity() {
            return Err(SyntaxError {
                message: format!(
                    "`{name}` takes {} argument{}, not {}",
                    function.arity(),
                    if function.arity() == 1 { "" } else { "s" },
                    args.len()
                ),
                span,
                hint: (function == Function::Atan2).then(|| "atan2(y, x) is the angle of the point (x, y)".into()),
            });
        }
        Ok(Ast::Call(function, args, span))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn show(ast: &Ast) -> String {
        match ast {
            Ast::Number(v, _) => format!("{v}"),
            Ast::Name(n, _) => n.clone(),
            Ast::Neg(a, _) => format!("(-{})", show(a)),
            Ast::Binary(op, a, b, _) => {
                let c = match op {
                    BinaryOp::Add => '+',
                    BinaryOp::Sub => '-',
                    BinaryOp::Mul => '*',
                    BinaryOp::Div => '/',
                    BinaryOp::Pow => '^',
                };
                format!("({} {c} {})", show(a), show(b))
            }
            Ast::Call(f, args, _) => {
                format!("{}({})", f.name(), args.iter().map(show).collect::<Vec<_>>().join(", "))
            }
        }
    }

    #[test]
    fn precedence_and_associativity() {
        let cases = [
            ("1 + 2 * 3", "(1 + (2 * 3))"),
            ("a - b - c", "((a - b) - c)"),
            ("a / b / c", "((a / b) / c)"),
            ("-x^2", "(-(x ^ 2))"),
            ("a^b^c", "(a ^ (b ^ c))"),
            ("2^-1", "(2 ^ (-1))"),
            ("m₁*l'*sin(θ₁ - θ₂)", "((m₁ * l') * sin((θ₁ - θ₂)))"),
            ("atan2(y, x) + .5e1", "(atan2(y, x) + 5)"),
            ("+(a)", "a"),
        ];
        for (text, expected) in cases {
            assert_eq!(show(&parse(text).unwrap()), expected, "{text}");
        }
    }

    #[test]
    fn errors_point_at_the_offending_part() {
        let cases: [(&str, &str, Span); 9] = [
            ("1 +", "expected a number", 3..3),
            ("sin(x", "expected `,` or `)`", 5..5),
            ("2x", "expected an operator", 1..2),
            ("sine(x)", "unknown function `sine`", 0..4),
            ("atan2(x)", "takes 2 arguments", 0..8),
            ("a − b", "unexpected character `−`", 2..5),
            ("(a + b))", "unmatched `)`", 7..8),
            ("1e400", "beyond the range", 0..5),
            ("sin x", "is a function", 0..3),
        ];
        for (text, message, span) in cases {
            let error = parse(text).unwrap_err();
            assert!(error.message.contains(message), "{text}: {}", error.message);
            assert_eq!(error.span, span, "{text}: {}", error.message);
        }
        assert_eq!(parse("sine(x)").unwrap_err().hint.as_deref(), Some("did you mean `sin`?"));
        assert!(parse("  ").unwrap_err().message.contains("empty"));
    }
}
