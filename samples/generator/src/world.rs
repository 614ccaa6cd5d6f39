//! The mission world: waypoints on three layers, their adjacency, robots,
//! points of interest, patrol routes and mandated meetings.
//!
//! Coordinates are integers in decimetres (as in the waypoint names of the
//! paper's Listing 2); distances are stored in centimetres (hundredths of
//! metres) so that they print exactly with two decimals.

use std::collections::{HashMap, HashSet};

use crate::geo::{self, Graph, SpatialHash, UnionFind};
use crate::rng::Rng;

/// The layer a waypoint belongs to. Aerial waypoints are used by the AAVs,
/// road waypoints by all ground robots, grass waypoints by the large UGVs only.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Layer {
    Air,
    Road,
    Grass,
}

impl Layer {
    pub fn prefix(self) -> &'static str {
        match self {
            Layer::Air => "wpa",
            Layer::Road => "wpr",
            Layer::Grass => "wpg",
        }
    }
}

/// The three robot types of the case study.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum RobotType {
    Aerial,
    UgvSmall,
    UgvLarge,
}

impl RobotType {
    pub const ALL: [RobotType; 3] = [RobotType::Aerial, RobotType::UgvSmall, RobotType::UgvLarge];

    /// The PDDL type name.
    pub fn pddl(self) -> &'static str {
        match self {
            RobotType::Aerial => "aerial",
            RobotType::UgvSmall => "ugv-small",
            RobotType::UgvLarge => "ugv-large",
        }
    }

    pub fn allows(self, layer: Layer) -> bool {
        match self {
            RobotType::Aerial => layer == Layer::Air,
            RobotType::UgvSmall => layer == Layer::Road,
            RobotType::UgvLarge => layer == Layer::Road || layer == Layer::Grass,
        }
    }

    /// Cruise speed in centimetres per second.
    pub fn speed_cms(self) -> u64 {
        match self {
            RobotType::Aerial => 500,
            RobotType::UgvSmall => 150,
            RobotType::UgvLarge => 100,
        }
    }

    /// Radius (dm) within which a robot of this type sees a point of interest.
    pub fn visibility_dm(self) -> i64 {
        match self {
            RobotType::Aerial => 1200,
            RobotType::UgvSmall => 500,
            RobotType::UgvLarge => 600,
        }
    }

    /// The layer whose waypoints host the points of interest given to this type.
    pub fn host_layer(self) -> Layer {
        match self {
            RobotType::Aerial => Layer::Air,
            RobotType::UgvSmall => Layer::Road,
            RobotType::UgvLarge => Layer::Grass,
        }
    }
}

/// Communication range (dm) between two robots, by their types.
pub fn com_range_dm(a: RobotType, b: RobotType) -> i64 {
    match (a == RobotType::Aerial, b == RobotType::Aerial) {
        (true, true) => 5000,
        (true, false) | (false, true) => 3000,
        (false, false) => 2000,
    }
}

/// Duration of an observation, in seconds.
pub const OBSERVE_S: u64 = 10;
/// Duration of a communication, in seconds.
pub const COMMUNICATE_S: u64 = 20;
/// Length of a meeting window, in seconds.
pub const WINDOW_S: u64 = 300;

#[derive(Debug, Clone)]
pub struct Waypoint {
    pub x: i64,
    pub y: i64,
    pub layer: Layer,
}

impl Waypoint {
    pub fn name(&self) -> String {
        format!("{}_{}_{}", self.layer.prefix(), self.x, self.y)
    }
}

#[derive(Debug, Clone)]
pub struct Poi {
    pub x: i64,
    pub y: i64,
    /// The waypoint the point was placed next to (it is visible from there).
    pub host: usize,
    /// The robot type whose patrol observes it.
    pub rtype: RobotType,
}

impl Poi {
    pub fn name(&self) -> String {
        format!("ptobs_{}_{}", self.x, self.y)
    }
}

#[derive(Debug, Clone)]
pub struct Robot {
    pub name: String,
    pub rtype: RobotType,
    pub start: usize,
}

#[derive(Debug, Clone)]
pub struct Patrol {
    pub name: String,
    pub rtype: RobotType,
    /// Where the patrol starts and ends.
    pub start: usize,
    /// Points of interest observed, with the waypoint each is observed from.
    pub observations: Vec<(usize, usize)>,
    /// The closed walk of the forward method: `walk[0] == walk[last] == start`.
    pub walk: Vec<usize>,
    /// Total length of the walk in centimetres.
    pub length_cm: u64,
    /// Duration of the patrol (moves at the type's speed plus observations), in centiseconds.
    pub duration_cs: u64,
}

#[derive(Debug, Clone)]
pub struct Meeting {
    pub r1: usize,
    pub r2: usize,
    pub open_s: u64,
    pub close_s: u64,
}

/// Size parameters of a world.
#[derive(Debug, Clone)]
pub struct Params {
    pub x0: i64,
    pub y0: i64,
    pub width: i64,
    pub height: i64,
    pub air_cols: usize,
    pub air_rows: usize,
    pub junction_cols: usize,
    pub junction_rows: usize,
    /// Target distance between road waypoints (dm).
    pub road_step: i64,
    pub grass: usize,
    pub pois: usize,
    pub pois_per_patrol: usize,
    pub meetings: usize,
}

impl Params {
    /// The case study of the paper: about 80 waypoints, 25 points of interest,
    /// 6 meetings, over a zone of 1.4 km × 1.1 km.
    pub fn surveillance() -> Self {
        Params {
            x0: 10000,
            y0: 1000,
            width: 14000,
            height: 11000,
            air_cols: 5,
            air_rows: 5,
            junction_cols: 4,
            junction_rows: 3,
            road_step: 1800,
            grass: 27,
            pois: 25,
            pois_per_patrol: 3,
            meetings: 6,
        }
    }

    /// The case study scaled by `area` (the zone's area and the number of
    /// waypoints grow linearly with it); points of interest are four times
    /// sparser than in the case study so that the domain stays small next to
    /// the problem.
    pub fn scaled(area: f64) -> Self {
        let base = Params::surveillance();
        let k = area.max(1.0).sqrt();
        let sc = |v: usize| ((v as f64) * k).round().max(1.0) as usize;
        Params {
            x0: base.x0,
            y0: base.y0,
            width: (base.width as f64 * k).round() as i64,
            height: (base.height as f64 * k).round() as i64,
            air_cols: sc(base.air_cols),
            air_rows: sc(base.air_rows),
            junction_cols: sc(base.junction_cols),
            junction_rows: sc(base.junction_rows),
            road_step: base.road_step,
            grass: ((base.grass as f64) * area).round() as usize,
            pois: ((base.pois as f64) * area / 4.0).round().max(base.pois as f64) as usize,
            pois_per_patrol: base.pois_per_patrol,
            meetings: base.meetings,
        }
    }
}

#[derive(Debug, Clone)]
pub struct World {
    pub params: Params,
    pub waypoints: Vec<Waypoint>,
    /// Undirected edges `(u, v, length in cm)` with `u < v`, sorted.
    pub edges: Vec<(usize, usize, u64)>,
    pub robots: Vec<Robot>,
    pub pois: Vec<Poi>,
    pub patrols: Vec<Patrol>,
    pub meetings: Vec<Meeting>,
    /// `(robot, waypoint, poi)`.
    pub visible: Vec<(usize, usize, usize)>,
    /// `(meeting, waypoint of r1, waypoint of r2)`.
    pub visible_com: Vec<(usize, usize, usize)>,
}

impl World {
    pub fn count_layer(&self, layer: Layer) -> usize {
        self.waypoints.iter().filter(|w| w.layer == layer).count()
    }

    /// Waypoints used by patrols (declared as domain constants), sorted.
    pub fn patrol_waypoints(&self) -> Vec<usize> {
        let mut set: Vec<usize> = self.patrols.iter().flat_map(|p| p.walk.iter().copied()).collect();
        set.sort_unstable();
        set.dedup();
        set
    }

    /// Points of interest used by patrols (declared as domain constants), sorted.
    pub fn patrol_pois(&self) -> Vec<usize> {
        let mut set: Vec<usize> =
            self.patrols.iter().flat_map(|p| p.observations.iter().map(|o| o.0)).collect();
        set.sort_unstable();
        set.dedup();
        set
    }
}

const ROBOTS: [(&str, RobotType); 8] = [
    ("ressac1", RobotType::Aerial),
    ("ressac2", RobotType::Aerial),
    ("effibot1", RobotType::UgvSmall),
    ("effibot2", RobotType::UgvSmall),
    ("effibot3", RobotType::UgvSmall),
    ("mona1", RobotType::UgvLarge),
    ("mona2", RobotType::UgvLarge),
    ("mona3", RobotType::UgvLarge),
];

/// Minimum distance between a grass waypoint and any other ground waypoint (dm).
const GRASS_SPACING: i64 = 700;
/// Minimum distance between a grass waypoint and a road (dm).
const GRASS_ROAD_CLEARANCE: i64 = 350;
/// Grass waypoints are linked to ground waypoints within this radius (dm).
const GRASS_LINK_RADIUS: i64 = 2300;
/// Minimum distance between two points of interest (dm).
const POI_SPACING: i64 = 200;
/// An edge is dropped when a detour at most this much longer exists (num/den).
const DETOUR: (u64, u64) = (108, 100);

pub fn generate(params: &Params, seed: u64) -> World {
    // One independent stream per stage, so that a stage's choices do not
    // shift when an earlier stage draws more or fewer numbers (e.g. with size).
    let stream = |k: u64| Rng::new(Rng::new(seed ^ k.wrapping_mul(0xA076_1D64_78BD_642F)).next_u64());
    let mut waypoints = Vec::new();
    let mut edges = Vec::new();

    gen_air(params, &mut stream(1), &mut waypoints, &mut edges);
    gen_ground(params, &mut stream(2), &mut waypoints, &mut edges);
    edges.sort_unstable();
    if let Some(((u, v, w), detour)) = geo::first_detour_violation(waypoints.len(), &edges) {
        panic!("edge {u}-{v} of {w} cm has a shorter detour of {detour} cm");
    }
    let names: HashSet<String> = waypoints.iter().map(Waypoint::name).collect();
    assert_eq!(names.len(), waypoints.len(), "two waypoints share a name");

    let graph = Graph::new(waypoints.len(), &edges);
    let robots = place_robots(params, &waypoints);
    let pois = place_pois(params, &mut stream(3), &waypoints);
    let mut world = World {
        params: params.clone(),
        waypoints,
        edges,
        robots,
        pois,
        patrols: Vec::new(),
        meetings: Vec::new(),
        visible: Vec::new(),
        visible_com: Vec::new(),
    };
    world.visible = compute_visible(&world);
    world.patrols = build_patrols(&world, &graph);
    let (meetings, visible_com) = plan_meetings(&world, &graph, &mut stream(4));
    world.meetings = meetings;
    world.visible_com = visible_com;
    world
}

fn in_zone(p: &Params, x: i64, y: i64, margin: i64) -> bool {
    x >= p.x0 + margin && x <= p.x0 + p.width - margin && y >= p.y0 + margin && y <= p.y0 + p.height - margin
}

/// A jittered grid of aerial waypoints, linked to their neighbours within 1.6
/// grid steps, without the links that a detour through a third waypoint
/// nearly matches.
fn gen_air(p: &Params, rng: &mut Rng, wps: &mut Vec<Waypoint>, edges: &mut Vec<(usize, usize, u64)>) {
    let sx = p.width / p.air_cols as i64;
    let sy = p.height / p.air_rows as i64;
    let first = wps.len();
    for j in 0..p.air_rows as i64 {
        for i in 0..p.air_cols as i64 {
            let x = p.x0 + i * sx + sx / 2 + rng.range(-sx / 5, sx / 5);
            let y = p.y0 + j * sy + sy / 2 + rng.range(-sy / 5, sy / 5);
            wps.push(Waypoint { x, y, layer: Layer::Air });
        }
    }
    let radius = sx.max(sy) * 8 / 5;
    let n = wps.len();
    let mut hash = SpatialHash::new(radius);
    for (id, wp) in wps.iter().enumerate().skip(first) {
        hash.insert(id, wp.x, wp.y);
    }
    let mut cand = Vec::new();
    for u in first..n {
        for v in hash.within(wps[u].x, wps[u].y, radius, |i| (wps[i].x, wps[i].y)) {
            if v > u {
                cand.push((u, v, geo::dist_cm(wps[u].x, wps[u].y, wps[v].x, wps[v].y)));
            }
        }
    }
    let kept = geo::prune_detours(n, &cand, &|_| false, DETOUR.0, DETOUR.1);
    check_connected(n, &kept, first..n, "aerial layer");
    edges.extend(kept);
}

fn check_connected(n: usize, edges: &[(usize, usize, u64)], nodes: std::ops::Range<usize>, what: &str) {
    let mut uf = UnionFind::new(n);
    for &(u, v, _) in edges {
        uf.union(u, v);
    }
    let first = nodes.start;
    for id in nodes {
        assert_eq!(uf.find(id), uf.find(first), "{what} is not connected");
    }
}

/// Roads (a jittered grid of junctions, some links removed, each link
/// subdivided into waypoints) and grass waypoints scattered away from the
/// roads, linked to nearby ground waypoints.
fn gen_ground(p: &Params, rng: &mut Rng, wps: &mut Vec<Waypoint>, edges: &mut Vec<(usize, usize, u64)>) {
    let first = wps.len();
    let (jc, jr) = (p.junction_cols as i64, p.junction_rows as i64);
    let sx = p.width / jc;
    let sy = p.height / jr;
    for j in 0..jr {
        for i in 0..jc {
            let x = p.x0 + i * sx + sx / 2 + rng.range(-sx / 7, sx / 7);
            let y = p.y0 + j * sy + sy / 2 + rng.range(-sy / 7, sy / 7);
            wps.push(Waypoint { x, y, layer: Layer::Road });
        }
    }
    let junction = |i: i64, j: i64| first + (j * jc + i) as usize;
    let mut links = Vec::new();
    for j in 0..jr {
        for i in 0..jc {
            if i + 1 < jc {
                links.push((junction(i, j), junction(i + 1, j)));
            }
            if j + 1 < jr {
                links.push((junction(i, j), junction(i, j + 1)));
            }
        }
    }
    // Remove about one link in seven, keeping the junctions connected.
    let mut order: Vec<usize> = (0..links.len()).collect();
    rng.shuffle(&mut order);
    let mut removed = vec![false; links.len()];
    let target = links.len() / 7;
    let mut count = 0;
    for l in order {
        if count == target {
            break;
        }
        removed[l] = true;
        let mut uf = UnionFind::new(wps.len());
        for (k, &(a, b)) in links.iter().enumerate() {
            if !removed[k] {
                uf.union(a, b);
            }
        }
        let root = uf.find(first);
        if (first..wps.len()).all(|id| uf.find(id) == root) {
            count += 1;
        } else {
            removed[l] = false;
        }
    }
    // Subdivide the links into road waypoints.
    let mut road_edges = Vec::new();
    for (k, &(a, b)) in links.iter().enumerate() {
        if removed[k] {
            continue;
        }
        let (ax, ay, bx, by) = (wps[a].x, wps[a].y, wps[b].x, wps[b].y);
        let len = ((dist2(ax, ay, bx, by)) as f64).sqrt();
        let parts = ((len / p.road_step as f64).round() as i64).max(1);
        let mut prev = a;
        for s in 1..parts {
            let jitter = rng.range(-p.road_step / 16, p.road_step / 16) as f64;
            let t = s as f64 / parts as f64;
            let x = ax as f64 + t * (bx - ax) as f64 - jitter * (by - ay) as f64 / len;
            let y = ay as f64 + t * (by - ay) as f64 + jitter * (bx - ax) as f64 / len;
            let id = wps.len();
            wps.push(Waypoint { x: x.round() as i64, y: y.round() as i64, layer: Layer::Road });
            road_edges.push((prev, id));
            prev = id;
        }
        road_edges.push((prev, b));
    }
    let road_end = wps.len();
    let max_road = road_edges
        .iter()
        .map(|&(a, b)| dist2(wps[a].x, wps[a].y, wps[b].x, wps[b].y))
        .max()
        .map_or(1, |d2| (d2 as f64).sqrt().ceil() as i64);
    // Index road segments by their midpoint for the clearance test.
    let mut seg_hash = SpatialHash::new(max_road.max(1));
    let mids: Vec<(i64, i64)> =
        road_edges.iter().map(|&(a, b)| ((wps[a].x + wps[b].x) / 2, (wps[a].y + wps[b].y) / 2)).collect();
    for (k, m) in mids.iter().enumerate() {
        seg_hash.insert(k, m.0, m.1);
    }
    let mut ground_hash = SpatialHash::new(GRASS_LINK_RADIUS);
    for (id, wp) in wps.iter().enumerate().take(road_end).skip(first) {
        ground_hash.insert(id, wp.x, wp.y);
    }
    // Scatter grass waypoints.
    let mut attempts = 0;
    let mut grass = 0;
    while grass < p.grass && attempts < p.grass * 80 {
        attempts += 1;
        let x = p.x0 + rng.range(250, p.width - 250);
        let y = p.y0 + rng.range(250, p.height - 250);
        let near = ground_hash.within(x, y, GRASS_SPACING, |i| (wps[i].x, wps[i].y));
        if !near.is_empty() {
            continue;
        }
        let segs = seg_hash.within(x, y, max_road / 2 + GRASS_ROAD_CLEARANCE, |k| mids[k]);
        let clear = segs.iter().all(|&k| {
            let (a, b) = road_edges[k];
            geo::seg_dist2((x, y), (wps[a].x, wps[a].y), (wps[b].x, wps[b].y))
                >= (GRASS_ROAD_CLEARANCE * GRASS_ROAD_CLEARANCE) as f64
        });
        if !clear {
            continue;
        }
        let id = wps.len();
        wps.push(Waypoint { x, y, layer: Layer::Grass });
        ground_hash.insert(id, x, y);
        grass += 1;
    }
    let n = wps.len();
    // Candidate links from grass waypoints.
    let mut set = HashSet::new();
    let mut cand: Vec<(usize, usize, u64)> = Vec::new();
    for &(a, b) in &road_edges {
        let (u, v) = (a.min(b), a.max(b));
        cand.push((u, v, geo::dist_cm(wps[u].x, wps[u].y, wps[v].x, wps[v].y)));
        set.insert((u, v));
    }
    let n_road_edges = cand.len();
    for g in road_end..n {
        for o in ground_hash.within(wps[g].x, wps[g].y, GRASS_LINK_RADIUS, |i| (wps[i].x, wps[i].y)) {
            if o == g {
                continue;
            }
            let (u, v) = (g.min(o), g.max(o));
            if set.insert((u, v)) {
                cand.push((u, v, geo::dist_cm(wps[u].x, wps[u].y, wps[v].x, wps[v].y)));
            }
        }
    }
    // Join grass clusters that are not connected to the roads.
    let mut uf = UnionFind::new(n);
    for &(u, v, _) in &cand {
        uf.union(u, v);
    }
    for g in road_end..n {
        if uf.find(g) == uf.find(first) {
            continue;
        }
        let mut radius = GRASS_LINK_RADIUS;
        loop {
            radius *= 2;
            let near = ground_hash.within(wps[g].x, wps[g].y, radius, |i| (wps[i].x, wps[i].y));
            let best = near
                .into_iter()
                .filter(|&o| uf.find(o) == uf.find(first))
                .min_by_key(|&o| (dist2(wps[g].x, wps[g].y, wps[o].x, wps[o].y), o));
            if let Some(o) = best {
                let (u, v) = (g.min(o), g.max(o));
                set.insert((u, v));
                cand.push((u, v, geo::dist_cm(wps[u].x, wps[u].y, wps[v].x, wps[v].y)));
                uf.union(u, v);
                break;
            }
        }
    }
    // Road links are kept as they are: only grass links are pruned.
    let kept = geo::prune_detours(n, &cand, &|e| e < n_road_edges, DETOUR.0, DETOUR.1);
    check_connected(n, &kept, first..n, "ground layer");
    let road_only: Vec<_> = kept.iter().copied().filter(|&(u, v, _)| u < road_end && v < road_end).collect();
    check_connected(n, &road_only, first..road_end, "road network");
    edges.extend(kept);
}

fn dist2(ax: i64, ay: i64, bx: i64, by: i64) -> i64 {
    geo::dist2(ax, ay, bx, by)
}

/// Starting positions: the allowed waypoints nearest to a base in the south-west of the zone.
fn place_robots(p: &Params, wps: &[Waypoint]) -> Vec<Robot> {
    let base = (p.x0 + p.width / 10, p.y0 + p.height / 10);
    let mut taken = HashSet::new();
    ROBOTS
        .iter()
        .map(|&(name, rtype)| {
            let start = (0..wps.len())
                .filter(|&w| rtype.allows(wps[w].layer) && !taken.contains(&w))
                .min_by_key(|&w| (dist2(base.0, base.1, wps[w].x, wps[w].y), w))
                .expect("no waypoint for a robot");
            taken.insert(start);
            Robot { name: name.to_string(), rtype, start }
        })
        .collect()
}

/// Points of interest, each placed near a distinct host waypoint of the layer
/// of the robot type that will observe it (types taken in turn).
fn place_pois(p: &Params, rng: &mut Rng, wps: &[Waypoint]) -> Vec<Poi> {
    let mut hosts: HashMap<RobotType, Vec<usize>> = HashMap::new();
    for t in RobotType::ALL {
        let mut list: Vec<usize> = (0..wps.len()).filter(|&w| wps[w].layer == t.host_layer()).collect();
        assert!(!list.is_empty(), "no {:?} waypoint to host points of interest", t.host_layer());
        rng.shuffle(&mut list);
        hosts.insert(t, list);
    }
    let mut pois: Vec<Poi> = Vec::new();
    let mut hash = SpatialHash::new(POI_SPACING * 4);
    let mut names = HashSet::new();
    let offset = rng.below(3) as usize;
    let mut cursor: HashMap<RobotType, usize> = HashMap::new();
    let mut i = 0usize;
    let mut failures = 0usize;
    while pois.len() < p.pois {
        let t = RobotType::ALL[(i + offset) % 3];
        i += 1;
        let list = &hosts[&t];
        let c = cursor.entry(t).or_insert(0);
        // The hosts of a type are tried in a shuffled order, then again.
        let host = list[*c % list.len()];
        *c += 1;
        let r = t.visibility_dm();
        let mut placed = false;
        for _ in 0..50 {
            let dx = rng.range(-r, r);
            let dy = rng.range(-r, r);
            let d2 = dx * dx + dy * dy;
            if d2 > (r * 4 / 5).pow(2) || d2 < (r / 5).pow(2) {
                continue;
            }
            let (x, y) = (wps[host].x + dx, wps[host].y + dy);
            if !in_zone(p, x, y, 100) {
                continue;
            }
            let poi = Poi { x, y, host, rtype: t };
            if !hash.within(x, y, POI_SPACING, |k| (pois[k].x, pois[k].y)).is_empty()
                || names.contains(&poi.name())
            {
                continue;
            }
            hash.insert(pois.len(), x, y);
            names.insert(poi.name());
            pois.push(poi);
            placed = true;
            break;
        }
        if !placed {
            failures += 1;
            assert!(failures < 100_000, "cannot place the points of interest");
        }
    }
    pois
}

/// `(visible r w p)`: every allowed waypoint of `r` within the visibility radius of `p`.
fn compute_visible(world: &World) -> Vec<(usize, usize, usize)> {
    let max_r = RobotType::ALL.iter().map(|t| t.visibility_dm()).max().unwrap_or(1);
    let mut hash = SpatialHash::new(max_r);
    for (k, p) in world.pois.iter().enumerate() {
        hash.insert(k, p.x, p.y);
    }
    let mut out = Vec::new();
    for (r, robot) in world.robots.iter().enumerate() {
        let radius = robot.rtype.visibility_dm();
        for (w, wp) in world.waypoints.iter().enumerate() {
            if !robot.rtype.allows(wp.layer) {
                continue;
            }
            for p in hash.within(wp.x, wp.y, radius, |k| (world.pois[k].x, world.pois[k].y)) {
                out.push((r, w, p));
            }
        }
    }
    out
}

/// Patrols: the points of interest of each robot type are ordered along a
/// serpentine over horizontal strips of the zone and cut into groups; each
/// group becomes a closed walk from a start waypoint through the waypoints
/// hosting its points (nearest first, along shortest paths) and back.
fn build_patrols(world: &World, graph: &Graph) -> Vec<Patrol> {
    let p = &world.params;
    let strips = ((p.height as f64 / 3700.0).round() as i64).max(1);
    let mut patrols = Vec::new();
    let mut counters: HashMap<RobotType, usize> = HashMap::new();
    for t in RobotType::ALL {
        let mut list: Vec<usize> = (0..world.pois.len()).filter(|&k| world.pois[k].rtype == t).collect();
        if list.is_empty() {
            continue;
        }
        let key = |k: usize| {
            let poi = &world.pois[k];
            let strip = ((poi.y - p.y0) * strips / p.height).clamp(0, strips - 1);
            (strip, if strip % 2 == 0 { poi.x } else { -poi.x }, k)
        };
        list.sort_by_key(|&k| key(k));
        let groups = list.len().div_ceil(p.pois_per_patrol);
        let allowed = |w: usize| t.allows(world.waypoints[w].layer);
        for g in 0..groups {
            let lo = list.len() * g / groups;
            let hi = list.len() * (g + 1) / groups;
            let group = &list[lo..hi];
            let mut hosts: Vec<usize> = group.iter().map(|&k| world.pois[k].host).collect();
            hosts.sort_unstable();
            hosts.dedup();
            let cx = hosts.iter().map(|&h| world.waypoints[h].x).sum::<i64>() / hosts.len() as i64;
            let cy = hosts.iter().map(|&h| world.waypoints[h].y).sum::<i64>() / hosts.len() as i64;
            let start = (0..world.waypoints.len())
                .filter(|&w| allowed(w) && !hosts.contains(&w))
                .min_by_key(|&w| (dist2(cx, cy, world.waypoints[w].x, world.waypoints[w].y), w))
                .expect("no start waypoint for a patrol");
            // Nearest-neighbour tour through the hosts, then back to the start.
            let mut walk = vec![start];
            let mut length_cm = 0;
            let mut current = start;
            let mut remaining = hosts.clone();
            while !remaining.is_empty() {
                let (dist, pred) = graph.dijkstra(current, &allowed, &remaining);
                let (idx, &next) = remaining
                    .iter()
                    .enumerate()
                    .min_by_key(|&(_, &h)| (dist[h], h))
                    .expect("remaining is not empty");
                assert!(dist[next] != u64::MAX, "patrol host unreachable");
                length_cm += dist[next];
                append_path(&mut walk, &pred, current, next);
                remaining.remove(idx);
                current = next;
            }
            let (dist, pred) = graph.dijkstra(current, &allowed, &[start]);
            length_cm += dist[start];
            append_path(&mut walk, &pred, current, start);
            let mut observations: Vec<(usize, usize)> =
                group.iter().map(|&k| (k, world.pois[k].host)).collect();
            // In the order of the forward walk.
            observations.sort_by_key(|&(k, h)| (walk.iter().position(|&w| w == h), k));
            let n = counters.entry(t).or_insert(0);
            *n += 1;
            let move_cs = (length_cm * 100).div_ceil(t.speed_cms());
            // Successive subtasks depend on each other (a move gives the next
            // step its position; an observe holds the position the next move
            // leaves), so a plan separates them by ε = 0.01 s, VAL's
            // tolerance: the patrol lasts that much longer per subtask after
            // the first, or its methods could not fit inside it.
            let subtasks = (walk.len() - 1 + observations.len()) as u64;
            patrols.push(Patrol {
                name: format!("patrol-{}-{}", t.pddl(), n),
                rtype: t,
                start,
                duration_cs: move_cs
                    + observations.len() as u64 * OBSERVE_S * 100
                    + subtasks.saturating_sub(1),
                observations,
                walk,
                length_cm,
            });
        }
    }
    patrols
}

/// Appends the shortest path `from` → `to` (given by predecessors) to `walk`,
/// whose last element is `from`.
fn append_path(walk: &mut Vec<usize>, pred: &[usize], from: usize, to: usize) {
    let mut path = Vec::new();
    let mut at = to;
    while at != from {
        path.push(at);
        at = pred[at];
        assert!(at != usize::MAX, "broken shortest path");
    }
    walk.extend(path.into_iter().rev());
}

/// Mandated meetings: pairs of robots that have positions from which they can
/// communicate (a random matching first, then other pairs, every robot in at
/// most two meetings), each with a window opening after both robots can reach
/// such positions from their starts, and after the robots' earlier windows.
fn plan_meetings(world: &World, graph: &Graph, rng: &mut Rng) -> (Vec<Meeting>, Vec<(usize, usize, usize)>) {
    let nr = world.robots.len();
    // Travel times (centiseconds) from each robot's start.
    let times: Vec<Vec<u64>> = world
        .robots
        .iter()
        .map(|r| {
            let allowed = |w: usize| r.rtype.allows(world.waypoints[w].layer);
            let (dist, _) = graph.dijkstra(r.start, &allowed, &[]);
            dist.into_iter()
                .map(|d| if d == u64::MAX { d } else { (d * 100).div_ceil(r.rtype.speed_cms()) })
                .collect()
        })
        .collect();
    let mut hash = SpatialHash::new(com_range_dm(RobotType::UgvSmall, RobotType::UgvSmall));
    for (w, wp) in world.waypoints.iter().enumerate() {
        hash.insert(w, wp.x, wp.y);
    }
    // The communication positions of a pair, and the earliest time (centiseconds)
    // both robots can be at one of them.
    let positions = |a: usize, b: usize| {
        let (ra, rb) = (&world.robots[a], &world.robots[b]);
        let range = com_range_dm(ra.rtype, rb.rtype);
        let mut facts = Vec::new();
        let mut best = u64::MAX;
        for (w1, wp) in world.waypoints.iter().enumerate() {
            if !ra.rtype.allows(wp.layer) {
                continue;
            }
            for w2 in hash.within(wp.x, wp.y, range, |w| (world.waypoints[w].x, world.waypoints[w].y)) {
                if w2 != w1 && rb.rtype.allows(world.waypoints[w2].layer) {
                    facts.push((w1, w2));
                    best = best.min(times[a][w1].max(times[b][w2]));
                }
            }
        }
        (facts, best)
    };
    let mut order: Vec<usize> = (0..nr).collect();
    rng.shuffle(&mut order);
    let mut candidates: Vec<(usize, usize)> =
        order.chunks(2).filter(|c| c.len() == 2).map(|c| (c[0].min(c[1]), c[0].max(c[1]))).collect();
    let mut others: Vec<(usize, usize)> =
        (0..nr).flat_map(|a| (a + 1..nr).map(move |b| (a, b))).filter(|p| !candidates.contains(p)).collect();
    rng.shuffle(&mut others);
    candidates.extend(others);
    let mut degree = vec![0usize; nr];
    let mut last_close = vec![0u64; nr];
    let mut meetings = Vec::new();
    let mut visible_com = Vec::new();
    for (a, b) in candidates {
        if meetings.len() == world.params.meetings {
            break;
        }
        if degree[a] == 2 || degree[b] == 2 {
            continue;
        }
        let (facts, best) = positions(a, b);
        if facts.is_empty() || best == u64::MAX {
            continue;
        }
        degree[a] += 1;
        degree[b] += 1;
        let slack = 200 + rng.below(400);
        let earliest = (best.div_ceil(100) + slack).max(last_close[a] + 300).max(last_close[b] + 300);
        let open_s = earliest.div_ceil(50) * 50;
        let close_s = open_s + WINDOW_S;
        last_close[a] = close_s;
        last_close[b] = close_s;
        let m = meetings.len();
        meetings.push(Meeting { r1: a, r2: b, open_s, close_s });
        visible_com.extend(facts.into_iter().map(|(w1, w2)| (m, w1, w2)));
    }
    (meetings, visible_com)
}
