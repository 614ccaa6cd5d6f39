//! Semantic highlighting: what each token of a file is. Names are resolved
//! by the occurrences goto and references use ([`super::occurrences`]), so
//! a name is coloured as what it refers to; the other tokens by what they
//! are (keywords, connectives, operators, numbers, comments).

use rowan::{TextRange, TextSize};
use rustc_hash::{FxHashMap, FxHashSet};

use super::{RefKind, occurrences};
use crate::db::{Db, Section, SourceFile, file_units, lower_item, parse};
use crate::model::ItemData;
use crate::semantics::check::domain_for;
use crate::semantics::symbols::domain_symbols;
use crate::syntax::{NodeOrToken, SyntaxKind};

/// What a token is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum HighlightKind {
    /// A section or field keyword, `define`, a connective.
    Keyword,
    /// `=`, `<`, `+`, `-`…
    Operator,
    Comment,
    Number,
    Type,
    Predicate,
    /// A numeric (or object) function.
    Function,
    Action,
    Task,
    Method,
    /// A constant of the domain.
    Constant,
    /// An object of a problem.
    Object,
    /// A parameter of an action, task, method or declaration.
    Parameter,
    /// A variable of a `forall` or `exists`.
    Variable,
    SubtaskId,
    Requirement,
    /// The name of a domain or a problem.
    UnitName,
}

/// A highlighted token.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HighlightToken {
    pub range: TextRange,
    pub kind: HighlightKind,
    /// Where the name is declared.
    pub declaration: bool,
    /// Built into the language (`object`, `number`).
    pub builtin: bool,
}

/// Words of the language that are not names.
fn is_language_word(word: &str) -> bool {
    matches!(
        word,
        "define"
            | "domain"
            | "problem"
            | "either"
            | "and"
            | "or"
            | "not"
            | "imply"
            | "forall"
            | "exists"
            | "when"
            | "at"
            | "over"
            | "start"
            | "end"
            | "all"
            | "preference"
            | "increase"
            | "decrease"
            | "assign"
            | "scale-up"
            | "scale-down"
            | "minimize"
            | "maximize"
            | "total-time"
            | "is-violated"
            | "always"
            | "sometime"
            | "within"
            | "at-most-once"
            | "sometime-after"
            | "sometime-before"
            | "always-within"
            | "hold-during"
            | "hold-after"
            | "sortof"
            | "undefined"
    )
}

fn is_operator(word: &str) -> bool {
    matches!(word, "=" | "<" | "<=" | ">" | ">=" | "+" | "-" | "*" | "/")
}

/// The semantic tokens of a file, in order. Names are classified by what
/// they refer to; a name that is neither declared nor a word of the
/// language is left out.
pub fn semantic_tokens(db: &dyn Db, file: SourceFile) -> Vec<HighlightToken> {
    if crate::db::is_plan_file(db, file) {
        return Vec::new();
    }
    // The names of every item, by their start.
    let mut names: FxHashMap<TextSize, (HighlightKind, bool, bool)> = FxHashMap::default();
    for &unit in file_units(db, file) {
        let syms = domain_for(db, unit).map(|d| domain_symbols(db, d));
        for &item in unit.items(db) {
            let offset = item.offset(db);
            let data = &lower_item(db, item).data;
            let params: FxHashSet<&str> = match data {
                ItemData::Action(a) => a.params.iter().map(|p| p.name.key()).collect(),
                ItemData::Task(t) => t.params.iter().map(|p| p.name.key()).collect(),
                ItemData::Method(m) => m.params.iter().map(|p| p.name.key()).collect(),
                ItemData::Htn(h) => h.params.iter().map(|p| p.name.key()).collect(),
                _ => FxHashSet::default(),
            };
            let declares_signatures = matches!(item.section(db), Section::Predicates | Section::Functions);
            occurrences(data, |o| {
                let key = o.name.key();
                let kind = match o.kind {
                    RefKind::Type => HighlightKind::Type,
                    RefKind::Predicate => HighlightKind::Predicate,
                    RefKind::Function => HighlightKind::Function,
                    RefKind::Callable if o.decl => match item.section(db) {
                        Section::Task => HighlightKind::Task,
                        _ => HighlightKind::Action,
                    },
                    RefKind::Callable => match syms {
                        Some(s) if s.tasks.contains_key(key) && !s.actions.contains_key(key) => {
                            HighlightKind::Task
                        }
                        _ => HighlightKind::Action,
                    },
                    RefKind::Task => HighlightKind::Task,
                    RefKind::Method => HighlightKind::Method,
                    RefKind::Object => {
                        let constant = match syms {
                            Some(s) => s.constants.contains_key(key),
                            None => item.section(db) == Section::Constants,
                        };
                        if constant { HighlightKind::Constant } else { HighlightKind::Object }
                    }
                    RefKind::Variable if declares_signatures || params.contains(key) => {
                        HighlightKind::Parameter
                    }
                    RefKind::Variable => HighlightKind::Variable,
                    RefKind::SubtaskId => HighlightKind::SubtaskId,
                    RefKind::Requirement => HighlightKind::Requirement,
                    RefKind::UnitName => HighlightKind::UnitName,
                };
                let builtin = o.kind == RefKind::Type && matches!(key, "object" | "number");
                names.insert(o.name.span.start() + offset, (kind, o.decl, builtin));
            });
        }
    }
    let mut out = Vec::new();
    for element in parse(db, file).syntax().descendants_with_tokens() {
        let NodeOrToken::Token(token) = element else { continue };
        // Text kept as too deep, or a stray `)`, is not read.
        if token.parent().is_some_and(|p| p.kind() == SyntaxKind::Error) {
            continue;
        }
        let range = token.text_range();
        let lexical = |kind| Some((kind, false, false));
        let found = match token.kind() {
            SyntaxKind::Comment => lexical(HighlightKind::Comment),
            SyntaxKind::Number => lexical(HighlightKind::Number),
            SyntaxKind::Variable | SyntaxKind::Keyword | SyntaxKind::Symbol => {
                match names.get(&range.start()) {
                    Some(&name) => Some(name),
                    None => {
                        let text = token.text();
                        match token.kind() {
                            SyntaxKind::Variable => lexical(HighlightKind::Variable),
                            SyntaxKind::Keyword => lexical(HighlightKind::Keyword),
                            _ if is_language_word(&text.to_ascii_lowercase()) => {
                                lexical(HighlightKind::Keyword)
                            }
                            // `- number` in `:functions`.
                            _ if text.eq_ignore_ascii_case("number") => {
                                Some((HighlightKind::Type, false, true))
                            }
                            // At the head of a list only: the `-` of a typed list is not one.
                            _ if is_operator(text) && heads_its_list(&token) => {
                                lexical(HighlightKind::Operator)
                            }
                            _ => None,
                        }
                    }
                }
            }
            _ => None,
        };
        if let Some((kind, declaration, builtin)) = found {
            out.push(HighlightToken { range, kind, declaration, builtin });
        }
    }
    out
}

/// Whether a token is the first of its list.
fn heads_its_list(token: &crate::syntax::SyntaxToken) -> bool {
    let mut prev = token.prev_sibling_or_token();
    while let Some(p) = prev {
        match p.kind() {
            SyntaxKind::LParen => return true,
            k if k.is_trivia() => prev = p.prev_sibling_or_token(),
            _ => return false,
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::AnalysisHost;

    /// Each token as `text: kind` with its modifiers.
    fn render(text: &str) -> String {
        let mut host = AnalysisHost::new();
        let file = host.set_file_text("domain.pddl", text);
        let mut out = String::new();
        for t in host.analysis().semantic_tokens(file).unwrap() {
            let mut line = format!("{:?} {:?}", &text[t.range], t.kind);
            if t.declaration {
                line.push_str(" declaration");
            }
            if t.builtin {
                line.push_str(" builtin");
            }
            out.push_str(&line);
            out.push('\n');
        }
        out
    }

    #[test]
    fn names_are_coloured_as_what_they_refer_to() {
        let text = "\
; Robots.
(define (domain rovers)
  (:requirements :typing :hierarchy)
  (:types robot - object waypoint)
  (:constants base - waypoint)
  (:predicates (at ?r - robot ?w - waypoint))
  (:functions (fuel ?r - robot) - number)
  (:task visit :parameters (?r - robot))
  (:action go :parameters (?r - robot)
    :precondition (and (forall (?w - waypoint) (at ?r ?w)) (>= (fuel ?r) 1.5))
    :effect (not (at ?r base)))
  (:method m :parameters (?r - robot) :task (visit ?r)
    :subtasks (and (t1 (go ?r)) (t2 (visit ?r)))
    :ordering (and (< t1 t2))))
";
        insta::assert_snapshot!(render(text));
    }

    #[test]
    fn objects_of_a_problem_and_unknown_names() {
        let mut host = AnalysisHost::new();
        host.set_file_text("d.pddl", "(define (domain d) (:constants c) (:predicates (p ?x)))");
        let text = "(define (problem q) (:domain d) (:objects o) (:init (p o) (p c) (zz o)))";
        let p = host.set_file_text("q.pddl", text);
        let tokens = host.analysis().semantic_tokens(p).unwrap();
        let kind_of = |word: &str| {
            let at = TextSize::from(text.find(word).expect("in the text") as u32);
            tokens.iter().find(|t| t.range.start() == at).map(|t| (t.kind, t.declaration))
        };
        assert_eq!(kind_of("o)"), Some((HighlightKind::Object, true)));
        assert_eq!(kind_of("o) (p c"), Some((HighlightKind::Object, false)));
        assert_eq!(kind_of("c)"), Some((HighlightKind::Constant, false)));
        assert_eq!(kind_of("q)"), Some((HighlightKind::UnitName, true)));
        assert_eq!(kind_of("d)"), Some((HighlightKind::UnitName, false)));
        // An undeclared predicate is still a predicate where it is used.
        assert_eq!(kind_of("zz"), Some((HighlightKind::Predicate, false)));
    }
}
