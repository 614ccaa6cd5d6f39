//! The language features that need a `:requirements` entry.

/// A language feature that needs a requirement.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Feature {
    Typing,
    NegativePreconditions,
    DisjunctivePreconditions,
    ExistentialPreconditions,
    UniversalPreconditions,
    ConditionalEffects,
    Equality,
    NumericFluents,
    DurativeActions,
    DurationInequalities,
    TimedInitialLiterals,
    DerivedPredicates,
    Preferences,
    Constraints,
    Hierarchy,
    MethodPreconditions,
}

impl Feature {
    /// The requirement to declare, and the requirements that also grant it.
    pub fn requirement(self) -> (&'static str, &'static [&'static str]) {
        match self {
            Feature::Typing => (":typing", &[":adl"]),
            Feature::NegativePreconditions => (":negative-preconditions", &[":adl"]),
            Feature::DisjunctivePreconditions => (":disjunctive-preconditions", &[":adl"]),
            Feature::ExistentialPreconditions => {
                (":existential-preconditions", &[":quantified-preconditions", ":adl"])
            }
            Feature::UniversalPreconditions => {
                (":universal-preconditions", &[":quantified-preconditions", ":adl"])
            }
            Feature::ConditionalEffects => (":conditional-effects", &[":adl"]),
            Feature::Equality => (":equality", &[":adl"]),
            Feature::NumericFluents => (":numeric-fluents", &[":fluents"]),
            Feature::DurativeActions => (":durative-actions", &[":time"]),
            Feature::DurationInequalities => (":duration-inequalities", &[]),
            Feature::TimedInitialLiterals => (":timed-initial-literals", &[]),
            Feature::DerivedPredicates => (":derived-predicates", &[]),
            Feature::Preferences => (":preferences", &[]),
            Feature::Constraints => (":constraints", &[":method-constraints"]),
            Feature::Hierarchy => (":hierarchy", &[":hierachie", ":htn"]),
            Feature::MethodPreconditions => (":method-preconditions", &[]),
        }
    }

    /// What the user wrote that needs it, for messages.
    pub fn what(self) -> &'static str {
        match self {
            Feature::Typing => "typed declarations",
            Feature::NegativePreconditions => "a negative condition `(not …)`",
            Feature::DisjunctivePreconditions => "a disjunctive condition (`or`, `imply`)",
            Feature::ExistentialPreconditions => "`exists`",
            Feature::UniversalPreconditions => "`forall` in a condition",
            Feature::ConditionalEffects => "a conditional effect (`when`, `forall`)",
            Feature::Equality => "`=` between objects",
            Feature::NumericFluents => "numeric fluents",
            Feature::DurativeActions => "durative actions",
            Feature::DurationInequalities => "a duration inequality",
            Feature::TimedInitialLiterals => "a timed initial literal `(at t …)`",
            Feature::DerivedPredicates => "`:derived`",
            Feature::Preferences => "`preference`",
            Feature::Constraints => "constraints",
            Feature::Hierarchy => "tasks and methods",
            Feature::MethodPreconditions => "a method precondition",
        }
    }
}

/// Requirements hipop knows (PDDL 1.2–3.1, PDDL+, HDDL 1.0 and 2.1).
pub const KNOWN_REQUIREMENTS: &[&str] = &[
    ":strips",
    ":typing",
    ":negative-preconditions",
    ":disjunctive-preconditions",
    ":equality",
    ":existential-preconditions",
    ":universal-preconditions",
    ":quantified-preconditions",
    ":conditional-effects",
    ":fluents",
    ":numeric-fluents",
    ":object-fluents",
    ":adl",
    ":durative-actions",
    ":duration-inequalities",
    ":continuous-effects",
    ":derived-predicates",
    ":timed-initial-literals",
    ":preferences",
    ":constraints",
    ":action-costs",
    ":time",
    ":hierarchy",
    ":method-preconditions",
    ":durative-methods",
    ":method-constraints",
];
