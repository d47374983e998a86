//! The widths the clean-up relies on: the declared widths of a module's ports, variables
//! and localparams ([`declarations`]), and the self-determined width of an expression when
//! it is certain ([`expr_width`]).

use std::collections::BTreeMap;

/// Width of a declaration line's `[h:l]`, or 1 without a range.
fn range_width(decl: &str) -> Option<u32> {
    match decl.find('[') {
        None => Some(1),
        Some(a) => {
            let b = a + decl[a..].find(']')?;
            let (h, l) = decl[a + 1..b].split_once(':')?;
            let h: i64 = h.trim().parse().ok()?;
            let l: i64 = l.trim().parse().ok()?;
            Some((h - l).unsigned_abs() as u32 + 1)
        }
    }
}

/// Width of a sized literal `N'h..`.
fn literal_width(lit: &str) -> Option<u32> {
    let (n, _) = lit.split_once('\'')?;
    n.parse().ok()
}

/// The declared widths of one module's ports, variables and localparams.
pub(super) fn declarations(lines: &[&str]) -> BTreeMap<String, u32> {
    let mut w = BTreeMap::new();
    for line in lines {
        let t = line.trim();
        let kind = t.split_whitespace().next().unwrap_or("");
        match kind {
            "input" | "output" | "reg" | "wire" | "inout" => {
                let name = t
                    .trim_end_matches([',', ';'])
                    .split_whitespace()
                    .last()
                    .unwrap_or("");
                if let Some(width) = range_width(t) {
                    w.insert(name.to_string(), width);
                }
            }
            "localparam" => {
                if let Some((lhs, rhs)) = t.trim_end_matches(';').split_once('=') {
                    let name = lhs.split_whitespace().last().unwrap_or("");
                    if let Some(width) = literal_width(rhs.trim()) {
                        w.insert(name.to_string(), width);
                    }
                }
            }
            _ => {}
        }
    }
    w
}

/// The width of `expr` when it is certain (see the module doc of `lint`), else None: Verilog's
/// self-determined width of identifiers, part and bit selects (`x[31:0]`, `x[32'h20]`), sized
/// literals, this rewrite's `sinedec_trunc_M_W(..)` (W), concatenations (the sum), `~` and `-` (the operand's), `& | ^ + -` (the widest
/// operand's) and `<< >>` (the left operand's; the amount is self-determined). A level of
/// parentheses that mixes shifts with other operators is uncertain (precedence would decide).
pub(super) fn expr_width(expr: &str, widths: &BTreeMap<String, u32>) -> Option<u32> {
    let mut p = WidthParser {
        s: expr.as_bytes(),
        i: 0,
        widths,
    };
    let w = p.binary()?;
    p.skip_ws();
    (p.i == p.s.len() && w > 0).then_some(w)
}

/// The recursive reader of [`expr_width`].
struct WidthParser<'a> {
    s: &'a [u8],
    i: usize,
    widths: &'a BTreeMap<String, u32>,
}

impl WidthParser<'_> {
    fn skip_ws(&mut self) {
        while self.s.get(self.i) == Some(&b' ') {
            self.i += 1;
        }
    }

    /// Operands joined by binary operators at one level of parentheses.
    fn binary(&mut self) -> Option<u32> {
        let mut w = self.unary()?;
        let (mut shift, mut other) = (false, false);
        loop {
            self.skip_ws();
            let c = match self.s.get(self.i) {
                Some(c) => *c,
                None => break,
            };
            let next = self.s.get(self.i + 1).copied();
            let is_shift = match c {
                b'<' | b'>' if next == Some(c) && self.s.get(self.i + 2) != Some(&c) => {
                    self.i += 2;
                    true
                }
                // `&&`, `||`, `^~` and reductions do not occur in the patterns rewritten.
                b'&' | b'|' if next == Some(c) => return None,
                b'&' | b'|' | b'^' | b'+' | b'-' => {
                    self.i += 1;
                    false
                }
                _ => break,
            };
            let r = self.unary()?;
            if is_shift {
                shift = true;
            } else {
                other = true;
                w = w.max(r);
            }
            if shift && other {
                return None;
            }
        }
        Some(w)
    }

    /// An operand: `~` or `-` and an operand, a parenthesized expression, a concatenation,
    /// an identifier with an optional select, or a sized literal.
    fn unary(&mut self) -> Option<u32> {
        self.skip_ws();
        let c = *self.s.get(self.i)?;
        let start = self.i;
        match c {
            b'~' | b'-' => {
                self.i += 1;
                if matches!(self.s.get(self.i), Some(b'&' | b'|' | b'^')) {
                    return None;
                }
                self.unary()
            }
            b'(' => {
                self.i += 1;
                let w = self.binary()?;
                self.skip_ws();
                (self.s.get(self.i) == Some(&b')')).then(|| self.i += 1)?;
                Some(w)
            }
            b'{' => {
                self.i += 1;
                let mut w = 0;
                loop {
                    w += self.binary()?;
                    self.skip_ws();
                    match self.s.get(self.i) {
                        Some(b',') => self.i += 1,
                        Some(b'}') => {
                            self.i += 1;
                            return Some(w);
                        }
                        _ => return None,
                    }
                }
            }
            c if c.is_ascii_alphabetic() || c == b'_' => {
                while self
                    .s
                    .get(self.i)
                    .is_some_and(|b| b.is_ascii_alphanumeric() || *b == b'_')
                {
                    self.i += 1;
                }
                let name = std::str::from_utf8(&self.s[start..self.i]).ok()?;
                // A truncation this rewrite wrote: W bits.
                if let (Some(mw), Some(b'(')) =
                    (name.strip_prefix("sinedec_trunc_"), self.s.get(self.i))
                {
                    let w: u32 = mw.split_once('_')?.1.parse().ok()?;
                    self.i += 1;
                    self.binary()?;
                    self.skip_ws();
                    (self.s.get(self.i) == Some(&b')')).then(|| self.i += 1)?;
                    return Some(w);
                }
                let w = *self.widths.get(name)?;
                if self.s.get(self.i) != Some(&b'[') {
                    return Some(w);
                }
                let close = self.i + self.s[self.i..].iter().position(|&b| b == b']')?;
                let sel = std::str::from_utf8(&self.s[self.i + 1..close]).ok()?;
                self.i = close + 1;
                match sel.split_once(':') {
                    Some((h, l)) => {
                        let h: u32 = h.trim().parse().ok()?;
                        let l: u32 = l.trim().parse().ok()?;
                        (h >= l && h < w).then_some(h - l + 1)
                    }
                    None => Some(1),
                }
            }
            c if c.is_ascii_digit() => {
                while self
                    .s
                    .get(self.i)
                    .is_some_and(|b| b.is_ascii_alphanumeric() || *b == b'\'')
                {
                    self.i += 1;
                }
                literal_width(std::str::from_utf8(&self.s[start..self.i]).ok()?)
            }
            _ => None,
        }
    }
}
