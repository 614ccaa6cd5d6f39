//! The lexer: splits text into tokens that cover every byte.

use super::kind::SyntaxKind;

/// The tokens of a text, as parallel arrays: token `i` is `kinds[i]`, and
/// covers `starts[i]..starts[i + 1]` (`starts` ends with the text's length).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Tokens {
    pub kinds: Vec<SyntaxKind>,
    pub starts: Vec<u32>,
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

/// The UTF-8 byte-order mark, U+FEFF.
pub const BOM: &str = "\u{feff}";

/// Lexes `text` into tokens that cover every byte.
pub fn lex(text: &str) -> Tokens {
    let mut tokens = Tokens { kinds: Vec::new(), starts: Vec::new() };
    lex_into(text, 0, &mut tokens);
    tokens.starts.push(text.len() as u32);
    tokens
}

/// Appends the tokens of `text`, which starts at offset `base` of the whole
/// text, without the final end offset.
fn lex_into(text: &str, base: u32, out: &mut Tokens) {
    let bytes = text.as_bytes();
    // Real files have a token every 2.5 (DriverLog) to 5 bytes.
    let capacity = bytes.len() / 2 + 16;
    out.kinds.reserve(capacity);
    out.starts.reserve(capacity + 1);
    let mut i = 0;
    // A UTF-8 byte-order mark at the start of the file (Windows editors write
    // one) is trivia, not part of an atom: the tree keeps it, so printing gives
    // the file back and offsets stay those of the file.
    if base == 0 && bytes.starts_with(BOM.as_bytes()) {
        out.kinds.push(SyntaxKind::Whitespace);
        out.starts.push(0);
        i = BOM.len();
    }
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
                i += 1;
                while i < bytes.len() && is_space(bytes[i]) {
                    i += 1;
                }
                SyntaxKind::Whitespace
            }
            first => {
                i += 1;
                while i < bytes.len() && !ends_atom(bytes[i]) {
                    i += 1;
                }
                // Most atoms are names: only a digit, `-` or `.` can start a number.
                match first {
                    b'?' => SyntaxKind::Variable,
                    b':' if i - start > 1 => SyntaxKind::Keyword,
                    b'0'..=b'9' | b'-' | b'.' => classify_atom(&text[start..i]),
                    _ => SyntaxKind::Symbol,
                }
            }
        };
        out.kinds.push(kind);
        out.starts.push(base + start as u32);
    }
}

/// Lexes like [`lex`], the two halves of a large text on two threads. The
/// split is right after a newline, which no comment or atom contains: only a
/// whitespace run can straddle it, and its two parts are joined back.
pub fn lex_parallel(text: &str) -> Tokens {
    // A thread costs about 40 µs to start and join; lexing 64 KiB about 300 µs.
    const PARALLEL_FROM_BYTES: usize = 64 << 10;
    if text.len() < PARALLEL_FROM_BYTES {
        return lex(text);
    }
    // Bytes, not `str`: the middle may fall inside a multi-byte character.
    let half = text.len() / 2;
    let Some(split) = text.as_bytes()[half..].iter().position(|&b| b == b'\n').map(|i| half + i + 1) else {
        return lex(text);
    };
    let (a, b) = text.split_at(split);
    let (mut first, second) = std::thread::scope(|scope| {
        let second = scope.spawn(|| {
            let mut tokens = Tokens { kinds: Vec::new(), starts: Vec::new() };
            lex_into(b, split as u32, &mut tokens);
            tokens
        });
        let mut first = Tokens { kinds: Vec::new(), starts: Vec::new() };
        lex_into(a, 0, &mut first);
        (first, second.join())
    });
    let Ok(second) = second else { return lex(text) };
    let joined = first.kinds.last() == Some(&SyntaxKind::Whitespace)
        && second.kinds.first() == Some(&SyntaxKind::Whitespace);
    let skip = usize::from(joined);
    first.kinds.extend_from_slice(&second.kinds[skip..]);
    first.starts.extend_from_slice(&second.starts[skip..]);
    first.starts.push(text.len() as u32);
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

/// Whether an atom that is not a [`SyntaxKind::Number`] starts like one
/// (`1e5`, `1e999`, `+3`, `1.2.3`, `2x`): where a number is expected, it is a
/// number PDDL does not have, not a name (names start with a letter).
pub fn looks_like_a_number(atom: &str) -> bool {
    if is_number(atom) {
        return false;
    }
    let unsigned = atom.strip_prefix(['-', '+']).unwrap_or(atom);
    let unsigned = unsigned.strip_prefix('.').unwrap_or(unsigned);
    unsigned.starts_with(|c: char| c.is_ascii_digit())
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
        let t = lex(text);
        assert_eq!(t.starts.len(), t.kinds.len() + 1);
        let range = |i: usize| t.starts[i] as usize..t.starts[i + 1] as usize;
        (0..t.kinds.len()).map(|i| (t.kinds[i], &text[range(i)])).collect()
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
    fn the_lexer_classifies_atoms_like_classify_atom() {
        for atom in
            ["?x", ":k", ":", "?", "12", "-3.5", "-", ".", ".5", "1.2.3", "-x", "a1", "été", "+1", "#t"]
        {
            assert_eq!(kinds(atom), vec![(classify_atom(atom), atom)], "{atom}");
        }
    }

    #[test]
    fn a_byte_order_mark_at_the_start_is_trivia() {
        use SyntaxKind::*;
        assert_eq!(
            kinds("\u{feff}(define)"),
            vec![(Whitespace, "\u{feff}"), (LParen, "("), (Symbol, "define"), (RParen, ")")]
        );
        assert_eq!(kinds("\u{feff}\n")[..2], [(Whitespace, "\u{feff}"), (Whitespace, "\n")]);
        // Elsewhere it is an ordinary character of an atom.
        assert_eq!(kinds("a\u{feff}b"), vec![(Symbol, "a\u{feff}b")]);
        assert_eq!(kinds("(\u{feff}x)")[1], (Symbol, "\u{feff}x"));
    }

    #[test]
    fn a_byte_order_mark_at_the_split_of_parallel_lexing_is_not_trivia() {
        let mut text = String::new();
        while text.len() < 100 << 10 {
            // Every line starts with one: so does the second half.
            text.push_str("\u{feff}(p a)\n");
        }
        assert_eq!(lex_parallel(&text), lex(&text));
    }

    #[test]
    fn atoms_that_look_like_numbers_but_are_not() {
        for atom in ["1e5", "1e999", "1E-3", "+3", "+.5", "1.2.3", "2x", "-1e2", ".5e1"] {
            assert_eq!(classify_atom(atom), SyntaxKind::Symbol, "{atom}");
            assert!(looks_like_a_number(atom), "{atom}");
        }
        for atom in ["12", "-3.5", ".5", "5.", "x1", "-", "+", "-x", "e5", "#t", "?x", "-.", "."] {
            assert!(!looks_like_a_number(atom), "{atom}");
        }
    }

    #[test]
    fn non_ascii_is_part_of_atoms() {
        assert_eq!(kinds("(été)")[1], (SyntaxKind::Symbol, "été"));
    }
}
