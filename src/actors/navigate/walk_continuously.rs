//! `walk_continuously` (thesis 5.2.4) as the actor runs it:
//! search_new_path, move, explore, over the navigation state of the
//! parent module.

use super::*;
use crate::actors::live::{show, Living};
use crate::actors::state::{EXPLORE, SEARCH_NEW_PATH, WALK};

impl Living {
    /// One frame of `walk_continuously`.
    pub(in crate::actors) fn walk_continuously(&mut self, dt: f32) {
        if self.memory.is_none() {
            // Without a memory there is nothing to plan on (`init`). A
            // tennis player walks straight to its place then, by design.
            if !self.navigation.tuning.open_court {
                self.note_once(
                    "no memory",
                    "runs walk_continuously without a visual memory (`init`): it has nothing to plan on and hands its goals to the next behaviour",
                );
            }
            return self.pop();
        }
        if self.edge.is_none() {
            self.note_once(
                "blind",
                "navigates without a vision window (`iVisionWinSize`): its memory stays empty, so it plans through everything it cannot see",
            );
        }
        // A tennis player looks at the ball through a narrow view and
        // runs on an open court by design.
        if !self.navigation.tuning.open_court {
            self.check_view(dt);
        }
        if self.stuck(dt) {
            return self.unstick();
        }
        if self.navigation.explorer.is_some() {
            return self.explore(dt);
        }
        if self.state == WALK && !self.navigation.path.is_empty() {
            return self.move_along(dt);
        }
        self.search_new_path();
    }

    /// Whether it has headed for a goal for [`STUCK_SECONDS`] without
    /// moving on by half a search voxel: a plan that keeps failing the
    /// collision test where it stands, a way that keeps being re-planned.
    fn stuck(&mut self, dt: f32) -> bool {
        let reach = self.half_search_voxel().unwrap_or(0.0);
        let nav = &mut self.navigation;
        if nav.destination.is_none() || self.eye.distance(nav.still_at) > reach {
            nav.still_at = self.eye;
            nav.still_for = 0.0;
            return false;
        }
        nav.still_for += dt;
        nav.still_for > STUCK_SECONDS
    }

    /// Stuck: the plans on its memory do not move it, so it explores
    /// from where it stands (Algorithm 1 walked for real, which moves it
    /// one free voxel at a time); stuck while exploring, it gives up.
    fn unstick(&mut self) {
        self.navigation.still_for = 0.0;
        let Some(dest) = self.navigation.destination else {
            return;
        };
        if self.navigation.explorer.is_some() {
            let why = format!(
                "stuck at ({}) for {STUCK_SECONDS} s while exploring toward its goal ({}): goal given up",
                show(self.eye),
                show(dest)
            );
            self.give_up_goal(why);
            return self.give_up();
        }
        self.note(&format!(
            "has not moved on from ({}) for {STUCK_SECONDS} s toward its goal ({}): it explores from there",
            show(self.eye),
            show(dest)
        ));
        self.navigation.path.clear();
        self.start_exploring(dest);
    }

    /// search_new_path: the destination (popped from the goal stack when
    /// there is none), then a plan to it on the memory.
    fn search_new_path(&mut self) {
        self.state = SEARCH_NEW_PATH;
        let dest = match self.navigation.destination {
            Some(d) => d,
            None => match self.goals.pop() {
                Some(g) => {
                    self.gave_up = None;
                    self.navigation.detours = 0;
                    *self.navigation.destination.insert(g)
                }
                None => return self.pop(),
            },
        };
        if self.eye.distance(dest) < self.eps_arrived_at(0) {
            self.navigation.destination = None;
            return;
        }
        let Some(h) = heuristics::heuristic(self.navigation.tuning.heuristic as u32) else {
            return self.pop();
        };
        let aim = self.aim(h, dest);
        let memory = self.memory.as_ref().expect("checked").octree();
        let cube = memory.cube();
        let to = |p: Vec3| p.as_dvec3().to_array();
        // A planar search aims at the goal's x, z at the eye's height; a
        // goal whose height lies outside the cube is still no goal in it.
        let outside = [(aim, "its goal"), (dest, "its goal"), (self.eye, "its eye")]
            .into_iter()
            .find(|(p, _)| memory.voxel(to(*p)).is_none());
        if let Some((p, what)) = outside {
            let why = format!(
                "{what} ({}) lies outside its memory's cube ({} … {} on each axis, `init`), where it cannot plan: goal ({}) given up",
                show(p),
                cube.min,
                cube.max,
                show(dest)
            );
            self.give_up_goal(why);
            return self.give_up();
        }
        self.navigation.band = self.ground_band(memory, h);
        let edge = self.grid(memory).edge();
        if edge < MIN_SEARCH_EDGE {
            let search = self.half_search_voxel().unwrap_or(0.0) * 2.0;
            self.note_once(
                "coarse",
                &format!(
                    "its search voxels of {search} (the `init` voxel edge {} × 2^rel_search_level {}) cut its memory's cube ({} … {}) into {edge} per edge, fewer than {MIN_SEARCH_EDGE}: too coarse to plan in; lower rel_search_level or the voxel edge",
                    cube.voxel_edge, self.navigation.tuning.rel_search_level, cube.min, cube.max
                ),
            );
        }
        if self.plan_to(h, dest) {
            return;
        }
        if self.navigation.failures > 0 {
            // Observing did not show a way: explore (5.2.2).
            return self.start_exploring(dest);
        }
        // Push itself and look around: the memory may then hold a way
        // (5.2.4).
        self.navigation.failures += 1;
        self.navigation.path.clear();
        self.look_around();
    }

    /// Plans a path to `dest` on the memory as it is now (Algorithms
    /// 1–4 on the grid of its last search) and walks it: false when the
    /// memory holds no way.
    fn plan_to(&mut self, h: &Heuristic, dest: Vec3) -> bool {
        let Some(memory) = self.memory.as_ref() else {
            return false;
        };
        let grid = self.grid(memory.octree());
        let aim = self.aim(h, dest);
        let to = |p: Vec3| p.as_dvec3().to_array();
        let from = match self.standing_voxel(&grid, h) {
            Some(v) if !planar(h) => glam::DVec3::from_array(grid.centre(v)).as_vec3(),
            _ => self.eye,
        };
        let points = match path::plan_on(
            &grid,
            to(from),
            to(aim),
            h,
            self.navigation.tuning.max_plan_voxels,
        ) {
            Ok(points) => points,
            Err(NoPlan::TooLong { visited }) => {
                // A plan this long costs the same at every voxel the
                // explore mode reaches: it explores without detours.
                self.navigation.detours = MAX_DETOURS;
                self.note_once(
                    "plan limit",
                    &format!(
                        "its path search to ({}) gave up after adding {visited} voxels to its path, over the limit of {}; it explores instead. Raise it with --max-plan-voxels N",
                        show(dest),
                        self.navigation.tuning.max_plan_voxels
                    ),
                );
                return false;
            }
            Err(_) => return false,
        };
        let flat = planar(h);
        let y = self.eye.y;
        self.navigation.path = points
            .iter()
            .skip(1)
            .map(|p| {
                let v = glam::DVec3::from_array(*p).as_vec3();
                if flat {
                    Vec3::new(v.x, y, v.z)
                } else {
                    v
                }
            })
            .collect();
        // The last key point is the goal itself, not its voxel.
        if let Some(last) = self.navigation.path.last_mut() {
            *last = aim;
        } else {
            self.navigation.path.push(aim);
        }
        self.navigation.failures = 0;
        self.navigation.explorer = None;
        self.navigation.target = None;
        self.state = WALK;
        true
    }

    /// Where a plan to `dest` ends: at the eye's height for a planar
    /// heuristic.
    fn aim(&self, h: &Heuristic, dest: Vec3) -> Vec3 {
        if planar(h) {
            Vec3::new(dest.x, self.eye.y, dest.z)
        } else {
            dest
        }
    }

    /// The explore mode (5.2.2) from where it stands toward `dest`, on
    /// the grid of its last search.
    fn start_exploring(&mut self, dest: Vec3) {
        let (Some(memory), Some(h)) = (
            self.memory.as_ref(),
            heuristics::heuristic(self.navigation.tuning.heuristic as u32),
        ) else {
            return;
        };
        let grid = self.grid(memory.octree());
        let to = |p: Vec3| p.as_dvec3().to_array();
        let start = self.standing_voxel(&grid, h);
        match start.zip(grid.voxel(to(self.aim(h, dest)))) {
            Some((start, end)) => {
                self.navigation.explorer = Some(Explorer::new(h, start, end));
                self.navigation.target = None;
                self.navigation.looked_around = false;
                self.state = EXPLORE;
            }
            None => {
                let why = format!(
                    "its goal ({}) or its eye ({}) lies outside its memory's cube: goal given up",
                    show(dest),
                    show(self.eye)
                );
                self.give_up_goal(why);
                self.give_up();
            }
        }
    }

    /// Leaves the explore mode for a plan on the memory as it is now,
    /// when one exists and it has not done so [`MAX_DETOURS`] times for
    /// this destination already.
    fn detour(&mut self) -> bool {
        let h = heuristics::heuristic(self.navigation.tuning.heuristic as u32);
        let (Some(h), Some(dest)) = (h, self.navigation.destination) else {
            return false;
        };
        if self.navigation.detours >= MAX_DETOURS || !self.plan_to(h, dest) {
            return false;
        }
        self.navigation.detours += 1;
        true
    }

    /// Whether the memory now holds something in the search voxel of the
    /// explore mode's next target.
    fn target_seen_occupied(&self, target: Vec3) -> bool {
        let Some(memory) = self.memory.as_ref() else {
            return false;
        };
        let grid = self.grid(memory.octree());
        grid.voxel(target.as_dvec3().to_array())
            .is_some_and(|v| !grid.is_empty(v))
    }

    /// The search grid of its memory at `rel_search_level`, laid on the
    /// ground of its last search.
    fn grid<'m>(&self, memory: &'m Octree) -> SearchGrid<'m> {
        SearchGrid::new(memory, self.navigation.tuning.rel_search_level).on(self.navigation.band)
    }

    /// For a planar heuristic, the layers laid on the ground its memory
    /// holds under its eye (docs/actors.md, "The ground of a planar
    /// search"): the floor is never in the layer it walks in, whatever
    /// its eye's height and the voxel sizes. None for a 3D heuristic, or
    /// when it has seen nothing under its eye.
    fn ground_band(&self, memory: &Octree, h: &Heuristic) -> Option<Band> {
        if !planar(h) {
            return None;
        }
        let eye = memory.voxel(self.eye.as_dvec3().to_array())?[1];
        let side = 1u32 << self.navigation.tuning.rel_search_level.min(memory.levels());
        let region = Region {
            centre: self.eye,
            range: GROUND_RANGE * side as f32 * memory.cube().voxel_edge as f32,
            plane: self.eye.y,
        };
        let ground = ground_layers(memory, &region, eye)?;
        Some(Band::new(eye, ground, side))
    }

    /// Pushes itself and runs `observe`, which pops it back.
    fn look_around(&mut self) {
        let dist = (self.look_at - self.eye).length().max(1.0);
        self.look_at = self.eye + self.gaze_along(self.heading()) * dist;
        self.push(Behaviour::of(Automata::WalkContinuously));
        self.activate(Behaviour::of(Automata::Observe));
    }

    /// Where the actor's eye goes in search voxel `v`: its centre, at the
    /// eye's height for a planar heuristic. For a support heuristic the
    /// voxel the eye is in is the actor's path voxel and the one under it
    /// its support, so the eye walks the centres (docs/actors.md, "The
    /// height of a support heuristic's path").
    fn key_point(&self, grid: &SearchGrid, v: Voxel) -> Vec3 {
        let c = glam::DVec3::from_array(grid.centre(v)).as_vec3();
        let flat =
            heuristics::heuristic(self.navigation.tuning.heuristic as u32).is_some_and(planar);
        let y = if flat { self.eye.y } else { c.y };
        Vec3::new(c.x, y, c.z)
    }

    /// The search voxel the actor stands in: the one its eye is in. For
    /// a support heuristic, when that one is not free above an occupied
    /// one (the eye halfway up or down a step, on the corner of four
    /// voxels), the one under or over it that is: where it comes from or
    /// goes to.
    fn standing_voxel(&self, grid: &SearchGrid, h: &Heuristic) -> Option<Voxel> {
        let v = grid.voxel(self.eye.as_dvec3().to_array())?;
        if planar(h) || !needs_support(h) {
            return Some(v);
        }
        let stands = |u: Voxel| {
            grid.is_empty(u)
                && u[1]
                    .checked_sub(1)
                    .is_some_and(|y| !grid.is_empty([u[0], y, u[2]]))
        };
        let below = v[1].checked_sub(1).map(|y| [v[0], y, v[2]]);
        let above = [v[0], v[1] + 1, v[2]];
        Some(
            [Some(v), below, Some(above)]
                .into_iter()
                .flatten()
                .find(|&u| stands(u))
                .unwrap_or(v),
        )
    }

    /// What `turtle 3` shows of the mental process: the path spline
    /// ahead ([`Self::path_ahead`]), or while exploring Algorithm 1's
    /// path list, from where the exploration began to the voxel the actor
    /// walks to.
    pub fn shown_path(&self) -> Vec<Vec3> {
        match (&self.navigation.explorer, &self.memory) {
            (Some(e), Some(memory)) => {
                let grid = self.grid(memory.octree());
                let path = e.path();
                let every = path.len().div_ceil(MAX_SHOWN).max(1);
                let mut shown: Vec<Vec3> = path
                    .iter()
                    .step_by(every)
                    .map(|&v| self.key_point(&grid, v))
                    .collect();
                // The voxel it walks to, always.
                if (path.len() - 1) % every != 0 {
                    shown.extend(path.last().map(|&v| self.key_point(&grid, v)));
                }
                shown
            }
            _ => self.path_ahead(),
        }
    }

    /// The goal cannot be reached: the next behaviour runs.
    fn give_up(&mut self) {
        self.navigation = Navigation::default();
        self.navigation.path.clear();
        self.pop();
    }

    /// explore (5.2.2): walks to the voxel Algorithm 1 chose, then asks
    /// it for the next one with the memory as it is now.
    fn explore(&mut self, dt: f32) {
        self.state = EXPLORE;
        if let Some(target) = self.navigation.target {
            if self.target_seen_occupied(target) {
                // What it walks to turned out occupied as it came near:
                // back to the voxel it came from.
                if let Some(e) = self.navigation.explorer.as_mut() {
                    let back = e.retreat();
                    let memory = self.memory.as_ref().expect("exploring");
                    let grid = self.grid(memory.octree());
                    self.navigation.target = back.map(|v| self.key_point(&grid, v));
                }
                return;
            }
            if !self.walk_to(target, dt) {
                return;
            }
            // At each voxel, the memory may now hold a way (a door seen
            // gone, a gap seen open): it walks that instead.
            if self.detour() {
                return;
            }
        }
        let (Some(memory), Some(e)) = (self.memory.as_ref(), self.navigation.explorer.as_mut())
        else {
            return;
        };
        let grid = SearchGrid::new(memory.octree(), self.navigation.tuning.rel_search_level)
            .on(self.navigation.band);
        let h = e.heuristic();
        if !self.navigation.looked_around
            && e.dead_end(|v| grid.is_empty(v))
            && needs_support(h)
            && e.path()
                .last()
                .is_some_and(|&v| ground_unseen_beside(&grid, v))
        {
            // A voxel just reached with no way on under what it has seen,
            // beside ground it has not seen: before walking back it looks
            // around (observe, as when no path is found), then takes the
            // voxel's candidates again.
            e.reopen();
            self.navigation.looked_around = true;
            return self.look_around();
        }
        match e.step(|v| grid.is_empty(v)) {
            ExplorerStep::Go(v) => {
                self.navigation.looked_around = false;
                self.navigation.target = Some(self.key_point(&grid, v));
            }
            ExplorerStep::Arrived => {
                // In the goal's voxel: the last steps to the goal itself.
                self.navigation.explorer = None;
                self.navigation.target = None;
                if let Some(d) = self.navigation.destination {
                    self.navigation.path = vec![d];
                    self.state = WALK;
                }
            }
            ExplorerStep::Enclosed => {
                if self.detour() {
                    return;
                }
                let e = self.navigation.explorer.as_ref().expect("exploring");
                let why = format!(
                    "its goal ({goal}) is out of reach: exploring, it walked every search voxel heuristic {h} reaches from where it began within its memory's cube ({steps} steps), and none leads to the goal's voxel: goal given up",
                    goal = self.navigation.destination.map_or("?".into(), show),
                    steps = e.visited(),
                    h = self.navigation.tuning.heuristic
                );
                self.give_up_goal(why);
                self.give_up();
            }
        }
    }

    /// move: along the path spline at `speed`, after checking the next
    /// `ahead` key points; a piece is laid from where the actor is, along
    /// its heading, whenever the key points ahead changed (a new plan, or
    /// Algorithm 5 dropped some).
    fn move_along(&mut self, dt: f32) {
        if self.path_blocked() {
            self.navigation.path.clear();
            self.search_new_path();
            return self.blocked_at_once();
        }
        self.optimise();
        let nav = &mut self.navigation;
        let piece = match nav.piece.take() {
            Some(p) if p.leads_along(&nav.path) => p,
            _ => {
                nav.travelled = 0.0;
                match Piece::new(self.eye, nav.heading, &nav.path, nav.tuning.inertia) {
                    Some(p) => p,
                    None => return self.search_new_path(),
                }
            }
        };
        nav.travelled += (self.speed * dt).max(1e-4);
        let (at, heading) = piece.along(nav.travelled);
        if let Some(stop) = self.step_stop(at) {
            // The way runs into what it sees or remembers: it stops
            // short and plans again on what it now knows.
            self.eye = stop;
            self.navigation.path.clear();
            return self.search_new_path();
        }
        self.eye = at;
        self.navigation.heading = heading;
        // It looks the way it walks, also when a step ends its piece: a
        // walker fast enough to end one every frame never turned its
        // eyes to its way, and walked blind into walls (issue 54).
        self.face(heading);
        let nav = &mut self.navigation;
        if nav.travelled < piece.length() {
            nav.piece = Some(piece);
            return;
        }
        nav.path.remove(0);
        if nav.path.is_empty() {
            // At the goal: the next one, or the next behaviour.
            nav.destination = None;
            nav.failures = 0;
            nav.heading = Vec3::ZERO;
            self.state = SEARCH_NEW_PATH;
        }
    }

    /// A path planned just now that its own collision test blocks: the
    /// heuristic plans where `coll_test_func` finds no way (table G.1), so
    /// planning again would give the same path every frame. It says so
    /// and explores from where it stands.
    fn blocked_at_once(&mut self) {
        let Some(dest) = self.navigation.destination else {
            return;
        };
        if self.state != WALK {
            return;
        }
        let Some(blocked) = self.first_blocked() else {
            return;
        };
        self.note_once(
            "disagree",
            &format!(
                "heuristic {} planned a path to ({}) through ({}), where its collision test coll_test_func {} finds no way (table G.1): it explores from there",
                self.navigation.tuning.heuristic,
                show(dest),
                show(blocked),
                self.navigation.tuning.coll_test_func
            ),
        );
        self.navigation.path.clear();
        self.start_exploring(dest);
    }

    /// The spline ahead of a walking actor, dotted every half search
    /// voxel: what `turtle` 3 draws.
    pub fn path_ahead(&self) -> Vec<Vec3> {
        let Some(half) = self.half_search_voxel() else {
            return Vec::new();
        };
        let length: f32 = std::iter::once(self.eye)
            .chain(self.navigation.path.iter().copied())
            .collect::<Vec<_>>()
            .windows(2)
            .map(|w| w[0].distance(w[1]))
            .sum();
        let spacing = half.max(length / MAX_SHOWN as f32);
        let nav = &self.navigation;
        let current = nav.piece.as_ref().map(|p| (p, nav.travelled));
        spline::ahead(
            current,
            self.eye,
            nav.heading,
            &self.navigation.path,
            self.navigation.tuning.inertia,
            spacing,
        )
    }

    /// One frame's straight walk toward `next` at `speed`; true once there.
    fn walk_to(&mut self, next: Vec3, dt: f32) -> bool {
        let to = next - self.eye;
        let reach = (self.speed * dt).max(1e-4);
        if to.length() <= reach {
            if let Some(stop) = self.step_stop(next) {
                self.eye = stop;
                return false;
            }
            self.eye = next;
            return true;
        }
        let heading = to.normalize();
        self.navigation.heading = heading;
        let at = self.eye + heading * reach;
        // Never into what it sees or remembers: the target is then seen
        // occupied, and the explorer turns back.
        self.eye = self.step_stop(at).unwrap_or(at);
        self.face(heading);
        false
    }

    /// Looks the way it walks ([`Self::gaze_along`]).
    fn face(&mut self, heading: Vec3) {
        let flat = Vec3::new(heading.x, 0.0, heading.z).normalize_or_zero();
        if flat != Vec3::ZERO {
            let dist = (self.look_at - self.eye).length().max(1.0);
            self.look_at = self.eye + self.gaze_along(flat) * dist;
        }
    }

    /// The direction it looks in when heading along `flat`: level; on a
    /// support heuristic pitched down, so that the lower edge of its
    /// window sees the ground a search voxel away (it may walk only where
    /// it has seen a support, and a level eye high over the ground with
    /// a narrow view sees none near it).
    fn gaze_along(&self, flat: Vec3) -> Vec3 {
        let support = heuristics::heuristic(self.navigation.tuning.heuristic as u32)
            .is_some_and(|h| planar(h) && needs_support(h));
        let (Some(memory), true) = (self.memory.as_ref(), support) else {
            return flat;
        };
        let cube = memory.octree().cube();
        let half = (self.fov as f32 / 20.0).to_radians();
        let near = self.half_search_voxel().unwrap_or(0.5) * 2.0;
        // Without a ground seen yet, the lower edge looks straight down.
        let lower = match self.navigation.band {
            Some(b) => {
                // The ground's surface lies somewhere in its layer: its
                // bottom, to see the nearest ground whatever.
                let ground = (cube.min + f64::from(b.floor) * cube.voxel_edge) as f32;
                (self.eye.y - ground).max(0.0).atan2(near)
            }
            None => std::f32::consts::FRAC_PI_2,
        };
        let pitch = (lower - half).clamp(0.0, std::f32::consts::FRAC_PI_2 - 0.05);
        flat * pitch.cos() - Vec3::Y * pitch.sin()
    }

    /// Algorithm 5, every `optim_rate` frames: of the next `optim_ahead`
    /// key points, the last one the actor sees clearly becomes the next:
    /// it walks straight to it, and the key points before it are dropped.
    fn optimise(&mut self) {
        self.navigation.since_optimised += 1;
        if self.navigation.tuning.optim_rate <= 0
            || self.navigation.since_optimised < self.navigation.tuning.optim_rate
        {
            return;
        }
        self.navigation.since_optimised = 0;
        let Some(window) = &self.window else {
            return;
        };
        let view = window.depth_view();
        let n = usize::try_from(self.navigation.tuning.optim_ahead)
            .unwrap_or(0)
            .min(self.navigation.path.len());
        let seen = |p: Vec3| clearly_visible(window, &view, p, self.size_actor);
        let shortcut = (1..n)
            .rev()
            .find(|&k| seen(self.navigation.path[k]) && self.free_way(self.navigation.path[k]));
        if let Some(k) = shortcut {
            self.navigation.path.drain(..k);
        }
    }

    /// Half the edge of a search voxel (`rel_search_level`), the step of
    /// the tests along a way; None without a memory.
    fn half_search_voxel(&self) -> Option<f32> {
        let edge = self.memory.as_ref()?.octree().cube().voxel_edge as f32;
        Some(edge * (1u32 << self.navigation.tuning.rel_search_level.min(20)) as f32 * 0.5)
    }

    /// Whether the straight way from the eye to `p`, as wide as the actor,
    /// passes only voxels the collision test finds free in the memory:
    /// what vision sees of the key point alone does not clear the corners
    /// on the way (a reading, docs/actors.md).
    fn free_way(&self, p: Vec3) -> bool {
        let (Some(free), Some(step)) = (self.collision_test(), self.half_search_voxel()) else {
            return false;
        };
        let way = p - self.eye;
        let side = Vec3::new(-way.z, 0.0, way.x).normalize_or_zero() * (self.size_actor * 0.5);
        let n = (way.length() / step).ceil().max(1.0) as u32;
        (0..=n).all(|i| {
            let c = self.eye + way * (i as f32 / n as f32);
            free(c) && free(c + side) && free(c - side)
        })
    }

    /// Whether one of the next `ahead` key points fails the collision
    /// test on the memory as it is now.
    fn path_blocked(&self) -> bool {
        self.first_blocked().is_some()
    }

    /// The first of the next `ahead` key points that fails the collision
    /// test on the memory as it is now.
    fn first_blocked(&self) -> Option<Vec3> {
        let free = self.collision_test()?;
        let ahead = self.navigation.tuning.ahead.max(1) as usize;
        self.navigation
            .path
            .iter()
            .take(ahead)
            .copied()
            .find(|&p| !free(p))
    }

    /// The collision test `coll_test_func` of a world point on the
    /// memory as it is now (false outside the memory's cube); None
    /// without a memory or a test.
    fn collision_test(&self) -> Option<impl Fn(Vec3) -> bool + '_> {
        let memory = self.memory.as_ref()?;
        let test = heuristics::heuristic(self.navigation.tuning.coll_test_func as u32)?;
        let grid = self.grid(memory.octree());
        Some(move |p: Vec3| {
            grid.voxel(p.as_dvec3().to_array())
                .is_some_and(|v| collision_free(test, v, |u| grid.is_empty(u)))
        })
    }
}
