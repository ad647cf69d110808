//! `walk_stepworthy` (thesis 5.9) as the actor runs it, over the
//! footing state of the parent module.

use super::*;
use crate::actors::live::{show, Living};
use crate::actors::state::{LOOK_AROUND, SEARCH_NEW_PATH, STOP, WALK};

impl Living {
    /// One frame of `walk_stepworthy`.
    pub(crate) fn walk_stepworthy(&mut self, dt: f32) {
        if self.memory.is_none() {
            // No memory, no map (`init`).
            self.note_once(
                "no memory",
                "runs walk_stepworthy without a visual memory (`init`): it cannot map footholds and hands its goals to the next behaviour",
            );
            return self.pop();
        }
        if self.edge.is_none() {
            self.note_once(
                "blind",
                "walks on footholds without a vision window (`iVisionWinSize`): it never sees a foothold",
            );
        }
        match self.footing.phase {
            Phase::Initialization => {
                self.footing.heading = self.heading();
                self.footing.phase = Phase::CreateMap;
                self.look_around_footholds();
            }
            Phase::CreateMap => self.create_map_and_search(),
            Phase::Walking => self.walking(dt),
        }
    }

    /// look_around: pushes itself and runs `observe`, which turns the eyes
    /// once around and pops it back, to create the map.
    fn look_around_footholds(&mut self) {
        self.state = LOOK_AROUND;
        self.footing.phase = Phase::CreateMap;
        self.footing.ahead.clear();
        if let Some(plane) = self.footing.plane {
            // The eyes look down at the plane two longest steps ahead.
            let reach = 2.0 * self.footing.settings.gait.df_max;
            let at = self.eye + self.footing.heading * reach;
            self.look_at = Vec3::new(at.x, plane, at.z);
        }
        self.push(Behaviour::of(Automata::WalkStepworthy));
        self.activate(Behaviour::of(Automata::Observe));
    }

    /// The local map around the eye, on the plane (found first, when the
    /// scene does not give it).
    fn create_map(&mut self) {
        let Some(memory) = self.memory.as_ref() else {
            return;
        };
        let f = &mut self.footing;
        let region = |plane| Region {
            centre: self.eye,
            range: f.settings.range,
            plane,
        };
        // The plane: the one it stands on once a map was made there;
        // the scene's as the memory holds it; else the busiest layer
        // under the actor's own height (never its own body).
        let octree = memory.octree();
        let below = self.eye.y - self.size_actor.max(MIN_STAND);
        let plane = f.plane.or_else(|| match f.settings.plane {
            Some(y) => Some(map::plane_near(octree, &region(y), y)),
            None => map::busiest_layer(octree, &region(0.0), below),
        });
        let Some(plane) = plane else {
            f.map.clear();
            return;
        };
        let stand = f
            .plane
            .map_or((self.eye.y - plane).max(MIN_STAND), |_| f.stand);
        // A foothold with something standing on it is none.
        let top = plane + stand;
        let (min_voxels, foot) = (f.settings.min_voxels, f.settings.foot);
        f.map = map::local_map(octree, &region(plane), min_voxels, foot)
            .into_iter()
            .filter(|m| !map::way_blocked(octree, plane, m.at, m.at, top))
            .collect();
        // The plane holds once it gave a map; an empty one is sought
        // again at the next look.
        if f.plane.is_none() && !f.map.is_empty() {
            f.plane = Some(plane);
            f.stand = stand;
        }
        f.last_plane = Some(plane);
    }

    /// What made its last map what it is, for a warning.
    fn explain_map(&self) -> String {
        let (Some(memory), Some(plane)) = (self.memory.as_ref(), self.footing.last_plane) else {
            return "it has no memory or has seen no plane under its eye".into();
        };
        let region = Region {
            centre: self.eye,
            range: self.footing.settings.range,
            plane,
        };
        format!(
            "its local map holds {} footholds: {}; memory {} voxels",
            self.footing.map.len(),
            map::explain(memory.octree(), &region, self.footing.settings.min_voxels),
            memory.voxels()
        )
    }

    /// Create the local map, pop a destination (end without one), and
    /// search a path to it; without one, look around again.
    fn create_map_and_search(&mut self) {
        self.create_map();
        if self.footing.destination.is_none() {
            match self.goals.pop() {
                Some(g) => {
                    self.gave_up = None;
                    self.footing.destination = Some(g);
                }
                None => {
                    // end: a later walk_stepworthy starts afresh.
                    self.state = STOP;
                    self.footing.phase = Phase::Initialization;
                    return self.pop();
                }
            }
        }
        self.state = SEARCH_NEW_PATH;
        if self.search_steps() {
            self.footing.failures = 0;
            self.footing.phase = Phase::Walking;
            self.state = WALK;
            return;
        }
        self.footing.failures += 1;
        if self.footing.failures >= MAX_LOOKS {
            // No way there in what it can see: the next destination.
            let why = format!(
                "no steps to its destination ({}) after looking around {MAX_LOOKS} times: {}; destination given up",
                self.footing.destination.map_or("none".into(), show),
                self.explain_map()
            );
            self.give_up_goal(why);
            self.footing.failures = 0;
            self.footing.destination = None;
        }
        self.look_around_footholds();
    }

    /// search_new_path: Dijkstra over walking states from the foothold
    /// closest to the actor (feet together, left foot, facing the
    /// destination) to the one closest to the destination; true when
    /// there is a path, which becomes the footholds ahead.
    fn search_steps(&mut self) -> bool {
        let f = &mut self.footing;
        let Some(dest) = f.destination else {
            return false;
        };
        let points: Vec<Vec2> = f.map.iter().map(Foothold::ground).collect();
        let closest = |p: Vec2| {
            (0..points.len()).min_by(|&a, &b| {
                points[a]
                    .distance_squared(p)
                    .total_cmp(&points[b].distance_squared(p))
            })
        };
        let here = ground(f.on.unwrap_or(self.eye));
        let (Some(start), Some(goal)) = (closest(here), closest(ground(dest))) else {
            return false;
        };
        let facing = (ground(dest) - points[start]).normalize_or_zero();
        let facing = if facing == Vec2::ZERO {
            ground(f.heading)
        } else {
            facing
        };
        let gait = &f.settings.gait;
        let weights = &f.settings.weights;
        let found = plan::plan(&points, start, goal, facing, gait, weights).or_else(|| {
            // No way to the destination's foothold in what it has seen:
            // as near to the destination as the map leads, if nearer.
            let near = reachable(&points, start, gait.df_max)
                .into_iter()
                .min_by(|&a, &b| {
                    let d = |i: usize| points[i].distance_squared(ground(dest));
                    d(a).total_cmp(&d(b)).then(a.cmp(&b))
                })
                .filter(|&i| i != start && i != goal)?;
            plan::plan(&points, start, near, facing, gait, weights)
        });
        let Some(found) = found else {
            return false;
        };
        let at = |i: usize| f.map[i].at;
        f.ahead = found
            .steps
            .iter()
            .map(|s| Planned {
                at: at(s.current),
                foot: s.foot,
                together: s.is_halt(),
            })
            .collect();
        // The start state is where the feet are; the first step onto it
        // when the actor is not there yet.
        // (as the map placed it now: a stone seen better moves a little).
        let edge = self
            .memory
            .as_ref()
            .map_or(0.0, |m| m.octree().cube().voxel_edge as f32);
        let radius = (f.map[start].voxels as f32 / std::f32::consts::PI).sqrt() * edge;
        if f.on
            .is_some_and(|on| ground(on).distance(points[start]) <= radius)
        {
            f.ahead.remove(0);
        }
        f.plans += 1;
        true
    }

    /// walking: one frame of the step under way, or the next step.
    fn walking(&mut self, dt: f32) {
        self.state = WALK;
        if let Some((motion, t)) = self.footing.motion {
            return self.move_body(motion, t + dt);
        }
        let Some(next) = self.footing.ahead.first().copied() else {
            return self.reached();
        };
        if self.obstacle_ahead() {
            let f = &mut self.footing;
            f.replans += 1;
            f.blocked += 1;
            if f.blocked >= MAX_LOOKS {
                // The map keeps leading into what the memory shows
                // blocked: the next destination.
                let why = format!(
                    "its planned steps to ({}) were blocked {MAX_LOOKS} times by what its memory holds over the footholds: destination given up",
                    f.destination.map_or("none".into(), show)
                );
                f.blocked = 0;
                f.destination = None;
                self.give_up_goal(why);
            }
            return self.look_around_footholds();
        }
        let from = self.footing.on.unwrap_or(self.eye);
        let to_next = flat(next.at - from);
        let assembled = self.footing.on.is_none() || self.footing.together;
        if assembled && to_next != Vec3::ZERO && angle(self.footing.heading, to_next) > TURN_ON_SPOT
        {
            // Feet together: it turns on the spot before the step.
            let turn = Motion::Turn {
                from: self.footing.heading,
                to: to_next,
                time: angle(self.footing.heading, to_next) / TURN_SPEED,
            };
            return self.move_body(turn, 0.0);
        }
        let length = ground(from).distance(ground(next.at));
        let time = if length < 1e-4 {
            HALT_TIME
        } else {
            (length / self.speed.max(1e-3)).max(MIN_STEP_TIME)
        };
        self.footing.foot = Some(next.foot);
        if self.footing.soles[0].is_none() {
            // Its first move: the feet stand where they stood.
            let f = &mut self.footing;
            f.soles = f.standing(self.eye, f.heading).map(Some);
        }
        let f = &self.footing;
        let foot = f.stepping(
            next.foot,
            next.at,
            next.together,
            f.standing(self.eye, f.heading),
        );
        self.move_body(
            Motion::Step {
                from,
                to: next.at,
                time,
                foot,
                together: next.together,
            },
            0.0,
        );
    }

    /// The body at time `t` of `motion`; at its end the step is done.
    fn move_body(&mut self, motion: Motion, t: f32) {
        let f = &mut self.footing;
        if f.soles[0].is_none() {
            // Its first move: the feet stand where they stood.
            f.soles = f.standing(self.eye, f.heading).map(Some);
        }
        let stand = f.stand;
        match motion {
            Motion::Turn { from, to, time } => {
                let s = if time > 0.0 { t / time } else { 1.0 };
                f.heading = turn(from, angle_to(from, to) * s.clamp(0.0, 1.0));
                if s >= 1.0 {
                    let standing = f.standing(self.eye, to);
                    f.soles = [0, 1].map(|k| Some(Footing::turned(k, standing, to)));
                    f.heading = to;
                    f.motion = None;
                } else {
                    f.motion = Some((motion, t));
                }
            }
            Motion::Step {
                from,
                to,
                time,
                foot: k,
                together,
            } => {
                let s = (t / time).min(1.0);
                let d = flat(to - from);
                if d != Vec3::ZERO {
                    f.heading = d;
                }
                let lift =
                    HOP * ground(from).distance(ground(to)) * (std::f32::consts::PI * s).sin();
                // The body over the middle of its feet: from between where
                // they stand to between the standing foot and where the
                // other lands.
                let standing = f.standing(self.eye, d);
                let landing = f.landing(k, to, together, standing);
                let start = standing[0].midpoint(standing[1]);
                let p = start.lerp(standing[1 - k].midpoint(landing), s);
                let base = f.plane.unwrap_or(p.y);
                self.eye = Vec3::new(p.x, base + stand + lift, p.z);
                if s >= 1.0 {
                    f.soles = standing.map(Some);
                    f.soles[k] = Some(landing);
                    f.on = Some(to);
                    f.blocked = 0;
                    f.together = f.ahead.first().is_some_and(|p| p.together);
                    f.ahead.remove(0);
                    f.motion = None;
                } else {
                    f.motion = Some((motion, t));
                }
            }
        }
        self.gaze();
    }

    /// The eyes look at the plane where the feet go two steps ahead (the
    /// last planned foothold near the end), else along the heading.
    fn gaze(&mut self) {
        let f = &self.footing;
        let plane = f.plane.unwrap_or(self.eye.y - f.stand);
        let target = f
            .ahead
            .get(2)
            .or(f.ahead.last())
            .map(|p| p.at)
            .filter(|p| ground(*p).distance(ground(self.eye)) > 0.5 * f.settings.gait.df_max)
            .unwrap_or_else(|| self.eye + f.heading * (2.0 * f.settings.gait.df_max));
        self.look_at = Vec3::new(target.x, plane, target.z);
    }

    /// Whether the memory, as vision keeps it, shows an obstacle on a
    /// voxel along the planned path: a planned foothold whose cells are
    /// gone, or something over a step's way.
    fn obstacle_ahead(&self) -> bool {
        let (Some(memory), Some(plane)) = (self.memory.as_ref(), self.footing.plane) else {
            return false;
        };
        let tree = memory.octree();
        let f = &self.footing;
        let edge = tree.cube().voxel_edge as f32;
        let need = (f.settings.min_voxels / 2).max(1);
        let top = plane + f.stand;
        let mut from = f.on.unwrap_or(Vec3::new(self.eye.x, plane, self.eye.z));
        let here = ground(from);
        let watched = CHECKED_STEPS * f.settings.gait.df_max;
        for p in f
            .ahead
            .iter()
            .take_while(|p| ground(p.at).distance(here) <= watched)
        {
            let size = f
                .map
                .iter()
                .find(|m| ground(m.at).distance(ground(p.at)) < 1e-4)
                .map_or(1, |m| m.voxels);
            let radius = (size as f32 / std::f32::consts::PI).sqrt() * edge + edge;
            if map::cells_near(tree, plane, p.at, radius) < need
                || map::way_blocked(tree, plane, from, p.at, top)
            {
                return true;
            }
            from = p.at;
        }
        false
    }

    /// The destination foothold is reached: the destination is done when
    /// it is within a longest step of it, or when this walk brought the
    /// actor no nearer (the map ends there); either way it looks around,
    /// maps and goes on.
    fn reached(&mut self) {
        let f = &mut self.footing;
        if let (Some(dest), Some(on)) = (f.destination, f.on) {
            let left = ground(dest).distance(ground(on));
            let near = left <= f.settings.gait.df_max;
            let stuck = f
                .stuck_at
                .is_some_and(|s| ground(s).distance(ground(on)) < 1e-4);
            if near || stuck {
                f.destination = None;
                f.stuck_at = None;
            } else {
                f.stuck_at = Some(on);
            }
        }
        self.look_around_footholds();
    }

    /// The material turtle 1 shows (6.3.4): red turning on the spot,
    /// white on the right foot, yellow on the left; None before a step.
    pub fn foothold_material(&self) -> Option<u32> {
        const RED: u32 = 4;
        const YELLOW: u32 = 5;
        const WHITE: u32 = 7;
        if self.footing.turning() {
            return Some(RED);
        }
        self.footing.foot.map(|f| match f {
            Foot::Right => WHITE,
            Foot::Left => YELLOW,
        })
    }
}
