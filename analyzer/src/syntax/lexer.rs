//! The lexer: splits text into tokens that cover every byte.

use super::kind::SyntaxKind;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Token {
    pub kind: SyntaxKind,
    pub len: u32,
}

/// Byte classes: whitespace, and the bytes that end an atom.
const SPACE: u8 = 1;
const DELIM: u8 = 2;

const CLASS: [u8; 256] = {
    let mut t = [0u8; 256];
    let spaces = [b' ', b'\t', b'\n', b'\r', 0x0b, 0x0c];
    let mut i = 0;
    while i < spaces.len() {
        t[spaces[i] as usize] = SPACE | DELIM;
        i += 1;
    }
    t[b'(' as usize] = DELIM;
    t[b')' as usize] = DELIM;
    t[b';' as usize] = DELIM;
    t
};

fn is_space(b: u8) -> bool {
    CLASS[b as usize] & SPACE != 0
}

fn ends_atom(b: u8) -> bool {
    CLASS[b as usize] & DELIM != 0
}

/// Lexes `text` into tokens whose lengths add up to `text.len()`.
pub fn lex(text: &str) -> Vec<Token> {
    let bytes = text.as_bytes();
    // About one token every five bytes in real files.
    let mut tokens = Vec::with_capacity(bytes.len() / 5 + 16);
    let mut i = 0;
    while i < bytes.len() {
        let start = i;
        let kind = match bytes[i] {
            b'(' => {
                i += 1;
                SyntaxKind::LParen
            }
            b')' => {
                i += 1;
                SyntaxKind::RParen
            }
            b';' => {
                while i < bytes.len() && bytes[i] != b'\n' && bytes[i] != b'\r' {
                    i += 1;
                }
                SyntaxKind::Comment
            }
            b if is_space(b) => {
                while i < bytes.len() && is_space(bytes[i]) {
                    i += 1;
                }
                SyntaxKind::Whitespace
            }
            _ => {
                i += 1;
                while i < bytes.len() && !ends_atom(bytes[i]) {
                    i += 1;
                }
                classify_atom(&text[start..i])
            }
        };
        tokens.push(Token { kind, len: (i - start) as u32 });
    }
    tokens
}

/// Lexes like [`lex`], the two halves of a large text on two threads. The
/// split is right after a newline, which no comment or atom contains: only a
/// whitespace run can straddle it, and its two parts are joined back.
pub fn lex_parallel(text: &str) -> Vec<Token> {
    const PARALLEL_FROM_BYTES: usize = 1 << 20;
    if text.len() < PARALLEL_FROM_BYTES {
        return lex(text);
    }
    let Some(split) = text[text.len() / 2..].find('\n').map(|i| text.len() / 2 + i + 1) else {
        return lex(text);
    };
    let (a, b) = text.split_at(split);
    let (mut first, second) = std::thread::scope(|scope| {
        let second = scope.spawn(|| lex(b));
        (lex(a), second.join())
    });
    let Ok(second) = second else { return lex(text) };
    let mut rest = second.as_slice();
    if let (Some(last), Some(next)) = (first.last_mut(), rest.first())
        && last.kind == SyntaxKind::Whitespace
        && next.kind == SyntaxKind::Whitespace
    {
        last.len += next.len;
        rest = &rest[1..];
    }
    first.extend_from_slice(rest);
    first
}

/// Classifies an atom by its first characters.
pub fn classify_atom(atom: &str) -> SyntaxKind {
    match atom.as_bytes() {
        [b'?', ..] => SyntaxKind::Variable,
        [b':', _, ..] => SyntaxKind::Keyword,
        _ if is_number(atom) => SyntaxKind::Number,
        _ => SyntaxKind::Symbol,
    }
}

fn is_number(atom: &str) -> bool {
    let digits = atom.strip_prefix('-').unwrap_or(atom);
    let mut seen_digit = false;
    let mut seen_dot = false;
    for b in digits.bytes() {
        match b {
            b'0'..=b'9' => seen_digit = true,
            b'.' if !seen_dot => seen_dot = true,
            _ => return false,
        }
    }
    seen_digit
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(text: &str) -> Vec<(SyntaxKind, &str)> {
        let mut at = 0;
        lex(text)
            .into_iter()
            .map(|t| {
                let s = &text[at..at + t.len as usize];
                at += t.len as usize;
                (t.kind, s)
            })
            .collect()
    }

    #[test]
    fn atoms_are_classified() {
        use SyntaxKind::*;
        assert_eq!(
            kinds("(at-r ?r :agent 3.5 -2 - #t);c\n"),
            vec![
                (LParen, "("),
                (Symbol, "at-r"),
                (Whitespace, " "),
                (Variable, "?r"),
                (Whitespace, " "),
                (Keyword, ":agent"),
                (Whitespace, " "),
                (Number, "3.5"),
                (Whitespace, " "),
                (Number, "-2"),
                (Whitespace, " "),
                (Symbol, "-"),
                (Whitespace, " "),
                (Symbol, "#t"),
                (RParen, ")"),
                (Comment, ";c"),
                (Whitespace, "\n"),
            ]
        );
    }

    #[test]
    fn parallel_lexing_equals_lexing() {
        let mut text = String::new();
        for i in 0..60_000 {
            text.push_str(&format!("  (p o{i}) ; c\n\n   "));
        }
        assert!(text.len() > 1 << 20);
        assert_eq!(lex_parallel(&text), lex(&text));
    }

    #[test]
    fn non_ascii_is_part_of_atoms() {
        assert_eq!(kinds("(été)")[1], (SyntaxKind::Symbol, "été"));
    }
}
