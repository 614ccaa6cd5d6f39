//! The semantic model: what a domain or problem item means, independent of its
//! layout. Every span is relative to the start of the item it comes from, so
//! that editing one item leaves the model of every other item equal.

mod lower;
mod name;

pub use lower::{
    ACTION_FIELDS, DURATIVE_ACTION_FIELDS, HTN_FIELDS, Lowered, METHOD_FIELDS, TASK_FIELDS, lower_chunk,
    lower_list,
};

pub use name::{Name, Symbol};
use rowan::{TextRange, TextSize};
/// A short string stored inline (names are short): no allocation per name.
pub type Str = compact_str::CompactString;

/// Whether `s` has an ASCII upper-case letter, tested eight bytes at a time:
/// a big problem has tens of thousands of names, and a loop over their bytes
/// was close to half the cost of making one.
fn has_ascii_uppercase(s: &[u8]) -> bool {
    /// Whether a byte of `w` is in `A..=Z`. Each addition sets a byte's high
    /// bit when the byte is at least some bound; clearing the high bits first
    /// keeps the carries inside their bytes, and `!w` leaves non-ASCII out.
    fn upper(w: u64) -> bool {
        const LOW: u64 = 0x7f7f_7f7f_7f7f_7f7f;
        let low = w & LOW;
        let at_least_a = low + 0x3f3f_3f3f_3f3f_3f3f; // 0x80 - b'A'
        let past_z = low + 0x2525_2525_2525_2525; // 0x80 - (b'Z' + 1)
        at_least_a & !past_z & !w & !LOW != 0
    }
    let byte = |i: usize| u64::from(s[i]);
    let half = |i: usize| u64::from(u32::from_le_bytes(s[i..i + 4].try_into().expect("four bytes")));
    let word = |i: usize| u64::from_le_bytes(s[i..i + 8].try_into().expect("eight bytes"));
    // Overlapping reads cover every byte, some twice, which an "any" test allows.
    let n = s.len();
    match n {
        0 => false,
        1..4 => upper(byte(0) | byte(n / 2) << 8 | byte(n - 1) << 16),
        4..8 => upper(half(0) | half(n - 4) << 32),
        _ => {
            let mut i = 0;
            while i + 8 < n {
                if upper(word(i)) {
                    return true;
                }
                i += 8;
            }
            upper(word(n - 8))
        }
    }
}

/// A type annotation: `- t`, `- (either a b)`, or none (`object`).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum TypeRef {
    Implicit,
    Named(Name),
    Either(Vec<Name>),
}

impl TypeRef {
    pub fn names(&self) -> &[Name] {
        match self {
            TypeRef::Implicit => &[],
            TypeRef::Named(n) => std::slice::from_ref(n),
            TypeRef::Either(ns) => ns,
        }
    }
}

/// `name - type` in parameters, objects, constants and types.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Typed {
    pub name: Name,
    pub ty: TypeRef,
}

#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Term {
    Var(Name),
    Const(Name),
    /// An object fluent or other function term, e.g. `(loc ?t)`.
    Func(Box<Fluent>),
}

impl Term {
    pub fn span(&self) -> TextRange {
        match self {
            Term::Var(n) | Term::Const(n) => n.span,
            Term::Func(f) => f.span,
        }
    }
}

/// The terms of an atom, a function term or a call. Most have one or two,
/// kept inline: a large `:init` is thousands of facts, and allocating their
/// terms (then freeing them with the model) was a large part of their cost.
pub type Args = smallvec::SmallVec<[Term; 2]>;

/// `(pred args…)`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Atom {
    pub pred: Name,
    pub args: Args,
    pub span: TextRange,
}

/// `(function args…)`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Fluent {
    pub func: Name,
    pub args: Args,
    pub span: TextRange,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TimeSpec {
    AtStart,
    AtEnd,
    OverAll,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CmpOp {
    Lt,
    Le,
    Eq,
    Ge,
    Gt,
}

impl CmpOp {
    pub fn parse(s: &str) -> Option<CmpOp> {
        Some(match s {
            "<" => CmpOp::Lt,
            "<=" => CmpOp::Le,
            "=" => CmpOp::Eq,
            ">=" => CmpOp::Ge,
            ">" => CmpOp::Gt,
            _ => return None,
        })
    }
}

/// A number, kept as written so that models compare exactly.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Number {
    pub text: Str,
    pub span: TextRange,
}

impl Number {
    pub fn value(&self) -> f64 {
        self.text.parse().unwrap_or(f64::NAN)
    }
}

#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum NumExpr {
    Number(Number),
    /// Boxed: fluents in expressions are few, and keep `Gd::Compare` small.
    Fluent(Box<Fluent>),
    /// `+ - * /` with two or more operands (`-` with one is negation).
    Op(Box<str>, Vec<NumExpr>, TextRange),
    /// `?duration`.
    Duration(TextRange),
    /// `(duration t1)` in HDDL 2.1 method constraints.
    TaskDuration(Name, TextRange),
    /// `#t` (continuous change) and `total-time`.
    Special(Box<str>, TextRange),
    /// A variable used as a number (object fluents are not numbers; reported by checks).
    Var(Name),
}

/// A goal description: preconditions, conditions, goals, constraints.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Gd {
    Atom(Atom),
    Equal(Term, Term, TextRange),
    /// The operands boxed: comparisons are few, atoms many, and an enum is as
    /// large as its largest variant.
    Compare(CmpOp, Box<NumExpr>, Box<NumExpr>, TextRange),
    Not(Box<Gd>, TextRange),
    And(Vec<Gd>, TextRange),
    Or(Vec<Gd>, TextRange),
    Imply(Box<Gd>, Box<Gd>, TextRange),
    Forall(Vec<Typed>, Box<Gd>, TextRange),
    Exists(Vec<Typed>, Box<Gd>, TextRange),
    Timed(TimeSpec, Box<Gd>, TextRange),
    /// `(preference name gd)` (PDDL 3).
    Preference(Option<Name>, Box<Gd>, TextRange),
    /// PDDL 3 / HDDL 2.1 modal constraints: `(always gd)`, `(at-most-once gd)`,
    /// `(sometime-before a b)`, `(before t1 gd)`, … The operands that are goal
    /// descriptions are kept; subtask ids in `ids`.
    Modal(Box<str>, Vec<Gd>, Box<[Name]>, TextRange),
    /// An ordering constraint inside `:constraints` (`(< t1 t2)`).
    Order(Ordering),
    /// `(sortof ?x - t)`: pandaPIparser's type constraint on a variable.
    Sortof(Term, TypeRef, TextRange),
}

/// Effects.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Effect {
    Add(Atom),
    Del(Atom, TextRange),
    And(Vec<Effect>, TextRange),
    Forall(Vec<Typed>, Box<Effect>, TextRange),
    /// The condition boxed, like [`Gd::Compare`]'s operands.
    When(Box<Gd>, Box<Effect>, TextRange),
    /// `(increase (f) e)`, `(assign …)`, …
    Numeric(Box<str>, Box<Fluent>, NumExpr, TextRange),
    /// `(assign (f) undefined)` and object-fluent assignment keep the target only.
    Timed(TimeSpec, Box<Effect>, TextRange),
}

/// What kind of action-like item an [`Action`] is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ActionKind {
    Action,
    Durative,
    Process,
    Event,
}

/// `(:action …)`, `(:durative-action …)`, PDDL+ `(:process …)` / `(:event …)`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Action {
    pub kind: ActionKind,
    pub name: Name,
    pub params: Vec<Typed>,
    pub agent: Vec<Name>,
    pub duration: Option<Gd>,
    pub precondition: Option<Gd>,
    pub effect: Option<Effect>,
}

/// `(:task …)`: an HDDL task, or a HiPOP abstract action with its own
/// duration, condition, effect and conflicts.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Task {
    pub name: Name,
    pub params: Vec<Typed>,
    pub agent: Vec<Name>,
    pub duration: Option<Gd>,
    pub precondition: Option<Gd>,
    pub effect: Option<Effect>,
    /// `:conflicts`, absent on a plain HDDL task (which is not a HiPOP
    /// abstract action); `:conflicts ()` is present and empty.
    pub conflicts: Option<Conflicts>,
}

/// The `:conflicts` of a task, with what an edit that adds atoms needs.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Conflicts {
    /// Atoms; variables that are not parameters are wildcards.
    pub atoms: Vec<Atom>,
    /// The `:conflicts` keyword.
    pub keyword: TextRange,
    /// The formula after it.
    pub span: TextRange,
    pub form: ConflictsForm,
}

/// How a `:conflicts` formula is written: where a new atom can go without
/// disturbing the user's layout and comments.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum ConflictsForm {
    /// `(and …)`: a new atom is inserted at `at` (after the last element, or
    /// before the `)` of an empty `(and)`), preceded by `sep` (a space, or a
    /// line break and the indentation of the last element).
    And { at: TextSize, sep: Str },
    /// One atom, closed by its `)`: it is wrapped into an `(and …)`.
    Atom,
    /// `()`.
    Empty,
    /// Anything else (an unclosed list, a malformed atom): no edit is offered.
    Other,
}

/// `(name args…)` naming a task or an action.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct TaskCall {
    pub name: Name,
    pub args: Args,
    pub span: TextRange,
}

/// `(id (name args…))` or `(name args…)` in a task network.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Subtask {
    pub id: Option<Name>,
    pub call: TaskCall,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Endpoint {
    Whole,
    Start,
    End,
}

#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct OrderPoint {
    pub id: Name,
    pub endpoint: Endpoint,
}

/// `(< t1 t2)`, `(t1 < t2)`, `(<= (end t1) (start t2))`, possibly negated.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Ordering {
    pub op: CmpOp,
    pub negated: bool,
    pub left: OrderPoint,
    pub right: OrderPoint,
    pub span: TextRange,
}

/// A task network: subtasks, orderings and constraints.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default)]
pub struct TaskNetwork {
    pub subtasks: Vec<Subtask>,
    /// `:ordered-subtasks`: the subtasks are totally ordered as listed.
    pub ordered: bool,
    pub ordering: Vec<Ordering>,
    pub constraints: Option<Gd>,
    /// `:causal-links` (PANDA's hybrid format).
    pub causal_links: Vec<CausalLink>,
}

/// `(t1 (p ?x) t2)`: `t1` produces `(p ?x)` for `t2`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct CausalLink {
    pub from: Name,
    pub atom: Atom,
    pub negated: bool,
    pub to: Name,
}

/// `(:method …)` or `(:durative-method …)`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Method {
    pub durative: bool,
    pub name: Name,
    pub params: Vec<Typed>,
    pub task: Option<TaskCall>,
    pub precondition: Option<Gd>,
    pub duration: Option<Gd>,
    pub effect: Option<Effect>,
    pub network: TaskNetwork,
}

/// `(pred ?x - t …)` in `:predicates`, or `(f ?x - t …) - number` in `:functions`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Signature {
    pub name: Name,
    pub params: Vec<Typed>,
    /// For functions: `number` or an object type (object fluents).
    pub result: TypeRef,
    pub span: TextRange,
}

/// An element of `:init`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum InitElement {
    Fact(Atom),
    /// `(not (p))` in a closed-world initial state.
    NotFact(Atom, TextRange),
    /// `(= (f args) 3.5)`.
    Assign(Fluent, NumExpr, TextRange),
    /// `(= (f args) obj)` for object fluents.
    AssignObject(Fluent, Name, TextRange),
    /// `(at 10 (p))` / `(at 10 (not (p)))`: timed initial literal.
    Timed(Number, Box<InitElement>, TextRange),
}

/// `(:htn …)` in a problem.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Htn {
    pub params: Vec<Typed>,
    pub network: TaskNetwork,
    pub span: TextRange,
}

/// The meaning of one section of a `define`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum ItemData {
    /// `(domain name)` or `(problem name)`.
    Header(Name),
    /// `(:domain name)` in a problem.
    DomainRef(Name),
    Requirements(Vec<Name>),
    Types(Vec<Typed>),
    Constants(Vec<Typed>),
    Predicates(Vec<Signature>),
    Functions(Vec<Signature>),
    Action(Box<Action>),
    Task(Box<Task>),
    Method(Box<Method>),
    /// `(:derived (p ?x) gd)`.
    Derived(Atom, Vec<Typed>, Gd),
    Objects(Vec<Typed>),
    Init(Vec<InitElement>),
    Goal(Gd),
    Htn(Htn),
    AllowedActions(Vec<Name>),
    /// `(:metric minimize expr)`.
    Metric(Name, NumExpr),
    /// `(:constraints gd)` (PDDL 3).
    Constraints(Gd),
    /// Anything that could not be understood (already reported).
    Unknown,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn upper_case_is_found_at_every_length_and_position() {
        for n in 0..40 {
            assert!(!has_ascii_uppercase(&vec![b'a'; n]));
            for i in 0..n {
                for b in 0..=u8::MAX {
                    let mut s = vec![b'a'; n];
                    s[i] = b;
                    assert_eq!(has_ascii_uppercase(&s), b.is_ascii_uppercase(), "{n} {i} {b}");
                }
            }
        }
        assert_eq!(Name::new("At-R", TextRange::default()).key(), "at-r");
    }

    /// A name gives back its text and its key, however it is stored.
    #[test]
    fn a_name_keeps_its_text_and_key() {
        let span = TextRange::new(3.into(), 9.into());
        for (text, key) in [
            ("", ""),
            ("at-r", "at-r"),
            ("At-R", "at-r"),
            ("ROVER", "rover"),
            ("seg_RW_0_1_a_long_name_past_inline", "seg_rw_0_1_a_long_name_past_inline"),
            ("Ärger-X", "Ärger-x"),
            ("ärger", "ärger"),
        ] {
            let n = Name::new(text, span);
            assert_eq!((n.text(), n.key(), n.span), (text, key, span));
            assert_eq!(n.clone(), n);
        }
        assert_ne!(Name::new("At", TextRange::default()), Name::new("at", TextRange::default()));
    }

    /// Names, atoms, conditions and effects are what large domains and
    /// `:init`s are made of: their sizes are the model's memory (before
    /// names were stored in one string, 56, 208, 208, 296 and 280 bytes).
    #[test]
    fn model_nodes_stay_small() {
        assert!(size_of::<Name>() <= 32, "{}", size_of::<Name>());
        assert!(size_of::<Atom>() <= 136, "{}", size_of::<Atom>());
        assert!(size_of::<Gd>() <= 136, "{}", size_of::<Gd>());
        assert!(size_of::<Effect>() <= 152, "{}", size_of::<Effect>());
        assert!(size_of::<InitElement>() <= 192, "{}", size_of::<InitElement>());
    }
}
