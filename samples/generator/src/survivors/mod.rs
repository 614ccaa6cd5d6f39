//! The Survivors benchmark of the HiPOP paper (section 4.4.1): teams of two
//! robots explore a crash site split into zones and bring the survivors to a
//! hospital; moving a survivor takes both robots of a team.
//!
//! The grid of the paper: 2 or 3 teams; 2, 3 or 4 rows of 2 zones; zones that
//! are square grids of 4, 9 or 16 locations; 2 to 5 survivors placed
//! pseudo-randomly; 2 hospitals. That is 2 × 3 × 3 × 4 = 72 problems, all of
//! one domain.
//!
//! - this file: the parameters, the map of a problem and the patrol routes;
//! - [`domain`]: the domain (the same for every problem);
//! - [`problem`]: a problem's text;
//! - [`witness`]: a plan that solves the problem, in VAL's format and in
//!   hipop's timed IPC 2020 hierarchical format;
//! - [`repair`]: the survivors-repair set (section 5.2): the problems after
//!   the disruptive events `startingPos`, `newSurvivor` and `survivorPos`.
//!
//! Times are integers in centiseconds and distances in centimetres, so that
//! they print exactly with two decimals.

pub mod domain;
pub mod problem;
pub mod repair;
pub mod witness;

use crate::geo::{self, Graph};
use crate::rng::Rng;

/// The number of teams of the paper's grid.
pub const TEAMS: [usize; 2] = [2, 3];
/// The number of rows of 2 zones.
pub const ROWS: [usize; 3] = [2, 3, 4];
/// The side of a zone (4, 9 or 16 locations).
pub const SIDES: [usize; 3] = [2, 3, 4];
/// The number of survivors.
pub const SURVIVORS: [usize; 4] = [2, 3, 4, 5];
/// Hospitals per problem.
pub const HOSPITALS: usize = 2;
/// Zones per row.
pub const ZONES_PER_ROW: usize = 2;

/// Distance between neighbouring locations before jitter, in decimetres.
pub const SPACING_DM: i64 = 100;
/// Largest jitter of a location's coordinates, in decimetres.
pub const JITTER_DM: i64 = 15;
/// Speed of every robot: 1 m/s, so a move lasts as many seconds as its
/// distance has metres.
pub const SPEED: &str = "1.0";
/// `explore` lasts 5 s.
pub const EXPLORE_CS: u64 = 500;
/// `rescue` (handing a survivor over to a hospital) lasts 10 s.
pub const RESCUE_CS: u64 = 1000;
/// `first-aid` (repair set) lasts 15 s.
pub const FIRST_AID_CS: u64 = 1500;
/// An evacuation lasts its first aid, this much more, and its carry.
pub const EVACUATE_EXTRA_CS: u64 = FIRST_AID_CS + 100;
/// A carried survivor slows the team down: `carry` lasts twice the move.
pub const CARRY_FACTOR: u64 = 2;
/// Separation of dependent happenings in the witness plans (VAL's tolerance).
pub const GAP_CS: u64 = 1;

/// The parameters of one problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct Params {
    pub teams: usize,
    pub rows: usize,
    /// Locations per side of a zone.
    pub side: usize,
    pub survivors: usize,
}

impl Params {
    /// The 72 problems of the paper's grid, in a fixed order.
    pub fn grid() -> Vec<Params> {
        let mut out = Vec::new();
        for teams in TEAMS {
            for rows in ROWS {
                for side in SIDES {
                    for survivors in SURVIVORS {
                        out.push(Params { teams, rows, side, survivors });
                    }
                }
            }
        }
        out
    }

    /// `p-t2-r3-z9-s4`: teams, rows, locations per zone, survivors.
    pub fn stem(&self) -> String {
        format!("p-t{}-r{}-z{}-s{}", self.teams, self.rows, self.side * self.side, self.survivors)
    }

    pub fn zones(&self) -> usize {
        self.rows * ZONES_PER_ROW
    }

    pub fn robots(&self) -> usize {
        self.teams * 2
    }
}

/// A cell of a zone: (row, column), from (1, 1) to (side, side).
pub type Cell = (usize, usize);

/// One step of a robot's walk through a zone.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Leg {
    Explore(Cell),
    Move(Cell, Cell),
}

/// How a patrol splits a zone between the two robots of a team.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Split {
    /// The first robot takes the first half of the rows, the second robot the
    /// rest (cells in boustrophedon order, row by row).
    Rows,
    /// The same, column by column (the transpose).
    Columns,
}

impl Split {
    pub const ALL: [Split; 2] = [Split::Rows, Split::Columns];

    pub fn suffix(self) -> &'static str {
        match self {
            Split::Rows => "by-rows",
            Split::Columns => "by-columns",
        }
    }
}

/// The name of the patrol task of zones of `side` × `side` locations.
pub fn patrol_name(side: usize) -> String {
    format!("patrol-{side}x{side}")
}

/// The zone type of zones of `side` × `side` locations.
pub fn zone_type(side: usize) -> String {
    format!("zone{side}x{side}")
}

/// The walks of the two robots of a team patrolling a zone: both start at
/// cell (1, 1) and end at cell (side, side); every cell is explored once, by
/// one of them. The walks are the same for every zone of that size (they are
/// the methods of the domain's patrol tasks).
pub fn walks(side: usize, split: Split) -> [Vec<Leg>; 2] {
    let mut order = Vec::with_capacity(side * side);
    for i in 1..=side {
        if i % 2 == 1 {
            order.extend((1..=side).map(|j| (i, j)));
        } else {
            order.extend((1..=side).rev().map(|j| (i, j)));
        }
    }
    let (first, second) = order.split_at((side * side).div_ceil(2));
    let (start, end) = ((1, 1), (side, side));
    let w1 = walk(start, first, end);
    let forward = walk(start, second, end);
    let reversed: Vec<Cell> = second.iter().rev().copied().collect();
    let backward = walk(start, &reversed, end);
    let w2 = if moves(&backward) < moves(&forward) { backward } else { forward };
    match split {
        Split::Rows => [w1, w2],
        Split::Columns => [transpose(&w1), transpose(&w2)],
    }
}

fn moves(legs: &[Leg]) -> usize {
    legs.iter().filter(|l| matches!(l, Leg::Move(..))).count()
}

fn transpose(legs: &[Leg]) -> Vec<Leg> {
    let t = |(i, j): Cell| (j, i);
    legs.iter()
        .map(|l| match *l {
            Leg::Explore(c) => Leg::Explore(t(c)),
            Leg::Move(a, b) => Leg::Move(t(a), t(b)),
        })
        .collect()
}

/// From `start`, explore each of `targets` in order, then go to `end`.
fn walk(start: Cell, targets: &[Cell], end: Cell) -> Vec<Leg> {
    let mut legs = Vec::new();
    let mut at = start;
    for &t in targets {
        path(at, t, &mut legs);
        legs.push(Leg::Explore(t));
        at = t;
    }
    path(at, end, &mut legs);
    legs
}

/// A shortest path on the grid: along the row first, then along the column.
fn path(from: Cell, to: Cell, legs: &mut Vec<Leg>) {
    let (mut i, mut j) = from;
    while j != to.1 {
        let next = if j < to.1 { j + 1 } else { j - 1 };
        legs.push(Leg::Move((i, j), (i, next)));
        j = next;
    }
    while i != to.0 {
        let next = if i < to.0 { i + 1 } else { i - 1 };
        legs.push(Leg::Move((i, j), (next, j)));
        i = next;
    }
}

/// The map of a problem: locations on a grid of zones, with jittered
/// coordinates, hospitals and survivors.
#[derive(Debug, Clone)]
pub struct Map {
    pub params: Params,
    /// Columns and rows of locations: `2 × side` by `rows × side`.
    pub width: usize,
    pub height: usize,
    /// Coordinates of each location in decimetres, indexed `y * width + x`.
    pub coords: Vec<(i64, i64)>,
    /// Undirected edges between neighbouring locations, with their distance in cm.
    pub edges: Vec<(usize, usize, u64)>,
    pub graph: Graph,
    pub hospitals: Vec<usize>,
    /// Where the survivors are, `s1` first.
    pub survivors: Vec<usize>,
    /// Where every robot starts: the first location of the first zone.
    pub base: usize,
}

impl Map {
    /// The map of `params`. Coordinates, hospitals and survivors only depend
    /// on the seed, the number of rows and the size of the zones: problems
    /// that differ by their teams share their map, and the survivors of a
    /// problem with fewer of them are the first ones of a problem with more.
    pub fn new(params: Params, seed: u64) -> Map {
        let (width, height) = (ZONES_PER_ROW * params.side, params.rows * params.side);
        let mut rng = Rng::new(seed ^ ((params.rows as u64) << 48) ^ ((params.side as u64) << 56));
        let mut coords = Vec::with_capacity(width * height);
        for y in 0..height {
            for x in 0..width {
                let jx = rng.range(-JITTER_DM, JITTER_DM);
                let jy = rng.range(-JITTER_DM, JITTER_DM);
                coords.push((x as i64 * SPACING_DM + jx, y as i64 * SPACING_DM + jy));
            }
        }
        let mut edges = Vec::new();
        for y in 0..height {
            for x in 0..width {
                let u = y * width + x;
                for v in [(x + 1 < width).then(|| u + 1), (y + 1 < height).then(|| u + width)]
                    .into_iter()
                    .flatten()
                {
                    let ((ax, ay), (bx, by)) = (coords[u], coords[v]);
                    edges.push((u, v, geo::dist_cm(ax, ay, bx, by)));
                }
            }
        }
        let graph = Graph::new(width * height, &edges);
        let mut locations: Vec<usize> = (0..width * height).collect();
        rng.shuffle(&mut locations);
        let hospitals = locations[..HOSPITALS].to_vec();
        let max_survivors = *SURVIVORS.iter().max().unwrap();
        let survivors = locations[HOSPITALS..HOSPITALS + max_survivors][..params.survivors].to_vec();
        Map { params, width, height, coords, edges, graph, hospitals, survivors, base: 0 }
    }

    /// The PDDL name of location `l`: `l<x>_<y>`.
    pub fn loc_name(&self, l: usize) -> String {
        format!("l{}_{}", l % self.width, l / self.width)
    }

    /// The location of cell `c` of zone `z` (zones numbered from 0, row by row).
    pub fn cell(&self, z: usize, (i, j): Cell) -> usize {
        let side = self.params.side;
        let (zr, zc) = (z / ZONES_PER_ROW, z % ZONES_PER_ROW);
        let (x, y) = (zc * side + j - 1, zr * side + i - 1);
        y * self.width + x
    }

    /// The distance between two neighbouring locations, in cm.
    pub fn dist(&self, a: usize, b: usize) -> u64 {
        self.graph.adj[a].iter().find(|&&(v, _)| v == b).map(|&(_, w)| w).expect("neighbouring locations")
    }

    /// A shortest path from `a` to `b` (the locations after `a`), and its length.
    pub fn path(&self, a: usize, b: usize) -> (Vec<usize>, u64) {
        let (dist, pred) = self.graph.dijkstra(a, &|_| true, &[b]);
        let mut out = Vec::new();
        let mut at = b;
        while at != a {
            out.push(at);
            at = pred[at];
        }
        out.reverse();
        (out, dist[b])
    }

    /// How long the walks of a patrol of zone `z` last, robot by robot, in cs
    /// (steps separated by [`GAP_CS`]).
    pub fn walk_spans(&self, z: usize, split: Split) -> [u64; 2] {
        walks(self.params.side, split).map(|legs| {
            let busy: u64 = legs
                .iter()
                .map(|l| match *l {
                    Leg::Explore(_) => EXPLORE_CS,
                    Leg::Move(a, b) => self.dist(self.cell(z, a), self.cell(z, b)),
                })
                .sum();
            busy + GAP_CS * (legs.len() as u64 - 1)
        })
    }

    /// The duration of the patrol of zone `z` (the `patrol-time` of the
    /// zone): the longest walk of either method, rounded up to the second.
    pub fn patrol_cs(&self, z: usize) -> u64 {
        let longest = Split::ALL.iter().flat_map(|&s| self.walk_spans(z, s)).max().unwrap();
        longest.div_ceil(100) * 100
    }
}

/// The name of zone `z` (from 0): `z1`, `z2`, … row by row.
pub fn zone_name(z: usize) -> String {
    format!("z{}", z + 1)
}

/// The robots of team `t` (from 0): `r1 r2`, `r3 r4`, …
pub fn team_robots(t: usize) -> [String; 2] {
    [format!("r{}", 2 * t + 1), format!("r{}", 2 * t + 2)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_is_the_papers() {
        let grid = Params::grid();
        assert_eq!(grid.len(), 72);
        let largest = grid.iter().max_by_key(|p| p.zones() * p.side * p.side).unwrap();
        assert_eq!(largest.zones() * largest.side * largest.side, 128, "4 x 2 x 16 locations");
    }

    /// Each method's walks start at c11, end at the opposite corner, move
    /// between neighbouring cells only and explore every cell exactly once.
    #[test]
    fn walks_cover_their_zone() {
        for side in SIDES {
            for split in Split::ALL {
                let mut explored = vec![0; side * side];
                for legs in walks(side, split) {
                    let mut at = (1, 1);
                    for leg in legs {
                        match leg {
                            Leg::Explore(c) => {
                                assert_eq!(c, at);
                                explored[(c.0 - 1) * side + c.1 - 1] += 1;
                            }
                            Leg::Move(a, b) => {
                                assert_eq!(a, at);
                                assert_eq!(a.0.abs_diff(b.0) + a.1.abs_diff(b.1), 1, "{a:?} → {b:?}");
                                assert!((1..=side).contains(&b.0) && (1..=side).contains(&b.1));
                                at = b;
                            }
                        }
                    }
                    assert_eq!(at, (side, side));
                }
                assert!(explored.iter().all(|&n| n == 1), "{side} {split:?}: {explored:?}");
            }
        }
    }

    #[test]
    fn maps_share_locations_and_survivors_across_problems() {
        let p = |teams, survivors| Params { teams, rows: 3, side: 3, survivors };
        let (a, b) = (Map::new(p(2, 2), 42), Map::new(p(3, 5), 42));
        assert_eq!(a.coords, b.coords);
        assert_eq!(a.hospitals, b.hospitals);
        assert_eq!(a.survivors[..], b.survivors[..2]);
        assert_eq!(b.survivors.len(), 5);
        let mut taken = b.survivors.clone();
        taken.extend(&b.hospitals);
        taken.sort_unstable();
        taken.dedup();
        assert_eq!(taken.len(), 7, "survivors and hospitals on distinct locations");
        // Every walk of a patrol fits in the patrol's duration.
        for z in 0..a.params.zones() {
            for split in Split::ALL {
                assert!(a.walk_spans(z, split).into_iter().all(|s| s <= a.patrol_cs(z)));
            }
        }
    }
}
