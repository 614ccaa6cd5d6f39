//! Which arguments of a step are its agents: the `:agent` parameters that the
//! HiPOP extension declares on actions and tasks (docs/language.md).

use rustc_hash::FxHashMap;

use super::{NameMatching, Step, normalise_name};
use crate::db::{Db, Section, SourceFile, UnitKind, file_units, lower_item};
use crate::model::{ItemData, Name, Typed};

/// For each action and task of a domain that declares `:agent`, the positions
/// of its agent parameters.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct AgentTable {
    matching: NameMatching,
    positions: FxHashMap<String, Vec<usize>>,
}

impl AgentTable {
    /// The agents of the actions and tasks of the domains in `file`.
    pub fn from_domain(db: &dyn Db, file: SourceFile, matching: NameMatching) -> AgentTable {
        let mut table = AgentTable { matching, positions: FxHashMap::default() };
        for unit in file_units(db, file).iter().filter(|u| u.kind(db) == UnitKind::Domain) {
            for &item in
                unit.items(db).iter().filter(|i| matches!(i.section(db), Section::Action | Section::Task))
            {
                match &lower_item(db, item).data {
                    ItemData::Action(a) => table.insert(&a.name, &a.params, &a.agent),
                    ItemData::Task(t) => table.insert(&t.name, &t.params, &t.agent),
                    _ => {}
                }
            }
        }
        table
    }

    fn insert(&mut self, name: &Name, params: &[Typed], agent: &[Name]) {
        if agent.is_empty() {
            return;
        }
        let positions: Vec<usize> =
            agent.iter().filter_map(|v| params.iter().position(|p| p.name.key() == v.key())).collect();
        if !positions.is_empty() {
            self.positions
                .entry(normalise_name(name.text(), self.matching).into_owned())
                .or_insert(positions);
        }
    }

    /// How the table compares names (actions, tasks, and agents between steps).
    pub fn matching(&self) -> NameMatching {
        self.matching
    }

    /// Whether no action or task declares agents.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// The agents of a step, as written in the plan: the agents a JSON plan
    /// gives, or the arguments at the `:agent` positions of its action or
    /// task. Empty when unknown (no `:agent`, an action the domain does not
    /// declare, too few arguments).
    pub fn agents_of(&self, step: &Step) -> Vec<String> {
        if !step.agents.is_empty() {
            return step.agents.iter().map(|a| a.text.to_string()).collect();
        }
        let Some(positions) = self.positions.get(normalise_name(&step.name.text, self.matching).as_ref())
        else {
            return Vec::new();
        };
        let agents: Option<Vec<String>> =
            positions.iter().map(|&i| step.args.get(i).map(|a| a.text.to_string())).collect();
        agents.unwrap_or_default()
    }
}
