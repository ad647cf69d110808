//! The behaviour stack (push, pop, activate) and the simple automata:
//! what an actor does with the `Living` state the behaviour module
//! types.

use super::*;
use crate::actors::live::{show, Living};
use crate::actors::state::{ALIGN, LISTEN_WORDS, LOOK_AROUND, STOP, TALK, WALK};

impl Living {
    /// Pushes a command string on the behaviour stack.
    pub fn push(&mut self, script: Behaviour) {
        self.stack.push(script);
    }

    /// The running automata ends: the next command string is popped, its
    /// commands set the state, and its automata runs from the start; with
    /// an empty stack the actor runs none.
    pub fn pop(&mut self) {
        self.progress = AutomataProgress::default();
        match self.stack.pop() {
            Some(script) => {
                for c in &script.commands {
                    self.apply(c);
                }
                self.automata = Some(script.automata);
            }
            None => self.automata = None,
        }
    }

    /// `e` par1 = 0 (C.6): the command string is pushed and popped at
    /// once, so its automata replaces the running one.
    pub fn activate(&mut self, script: Behaviour) {
        self.push(script);
        self.pop();
    }

    /// The running automata's work for this frame, after the sense step.
    pub fn act(&mut self, senses: &Senses, deeds: &mut Vec<Deed>) {
        match self.automata {
            Some(Automata::Observe) => self.observe(),
            Some(Automata::WalkLocal) => self.walk_local(senses.dt as f32),
            Some(Automata::AutoAlign) => self.auto_align(senses.dt as f32),
            Some(Automata::Talk) => self.talk(senses, deeds),
            Some(Automata::Listen) => self.listen(senses),
            Some(Automata::WalkContinuously) => self.walk_continuously(senses.dt as f32),
            Some(Automata::Referee) => self.referee(),
            Some(Automata::TennisErrorDetection) => self.tennis_error_detection(senses),
            Some(Automata::PlayTennis) => self.play_tennis(senses, deeds),
            Some(Automata::WalkStepworthy) => self.walk_stepworthy(senses.dt as f32),
            // watch: vision and memory only; L-system: the productions
            // act (5.10); follow_turtle: `M` moves it (the window).
            _ => {}
        }
    }

    /// Where the actor looks, horizontally (its body's direction).
    pub(crate) fn heading(&self) -> Vec3 {
        let d = self.look_at - self.eye;
        let flat = Vec3::new(d.x, 0.0, d.z).normalize_or_zero();
        if flat == Vec3::ZERO {
            Vec3::Z
        } else {
            flat
        }
    }

    fn look_along(&mut self, dir: Vec3) {
        let dist = (self.look_at - self.eye).length().max(1e-3);
        self.look_at = self.eye + dir * dist;
    }

    /// `observe` (5.3): the eyes turn once around, half a view angle a
    /// frame so that consecutive windows overlap, then the automata ends.
    fn observe(&mut self) {
        if self.progress.turned >= TAU - 1e-4 {
            return self.pop();
        }
        self.state = LOOK_AROUND;
        let step = self.half_view().min(TAU - self.progress.turned);
        self.turn_eyes(step);
        self.progress.turned += step;
    }

    /// Half the view angle, radians: how far the eyes turn a frame when
    /// looking around, so that consecutive windows overlap.
    pub(in crate::actors) fn half_view(&self) -> f32 {
        (self.fov as f32 / 20.0).to_radians()
    }

    /// The eyes turn by `a` radians to the left.
    pub(in crate::actors) fn turn_eyes(&mut self, a: f32) {
        let d = self.look_at - self.eye;
        self.look_at = self.eye + turn(d, a);
    }

    /// Turns the heading toward `dir` by at most `max` radians; returns
    /// the angle left.
    fn turn_toward(&mut self, dir: Vec3, max: f32) -> f32 {
        let h = self.heading();
        let a = angle_to(h, dir);
        let step = a.clamp(-max, max);
        self.look_along(turn(h, step));
        a - step
    }

    /// `walk_local` (table 5.1.1): to the actual goal by local vision
    /// only — toward the goal when the way ahead is free (`?31` = 0),
    /// turning away from the closest obstacle otherwise — at `speed`.
    /// It ends on arrival (`eps_arrived`), or at once without a goal.
    fn walk_local(&mut self, dt: f32) {
        let Some(goal) = self.actual_goal() else {
            return self.pop();
        };
        if self.sensor(33) > 0.0 {
            self.state = STOP;
            return self.pop();
        }
        self.state = WALK;
        let max = TURN_SPEED * dt;
        let obstacle = self.percepts.as_ref().map_or(0.0, |p| p.obstacle);
        if obstacle != 0.0 {
            // Obstacle on the left (−1): turn right, and the other way.
            let h = self.heading();
            self.look_along(turn(h, obstacle as f32 * max));
            return;
        }
        let to_goal = goal - self.eye;
        let flat = Vec3::new(to_goal.x, 0.0, to_goal.z).length();
        let eps = self.eps_arrived_at(0);
        if flat < eps {
            // Right over or under its goal, yet not there: walking on the
            // level brings it no nearer (issue 54: it stood for ever).
            let why = format!(
                "its goal ({}) lies {:.3} {} its eye, right {} it (within eps_arrived {eps} on the level): walk_local walks on the level and cannot reach it: goal given up",
                show(goal),
                to_goal.y.abs(),
                if to_goal.y < 0.0 { "below" } else { "above" },
                if to_goal.y < 0.0 { "under" } else { "over" },
            );
            self.give_up_goal(why);
            self.state = STOP;
            return self.pop();
        }
        self.turn_toward(to_goal, max);
        let step = (self.speed * dt).min(flat);
        let h = self.heading();
        // Never into what it sees or remembers (a fast walk jumped walls).
        let at = self.eye + h * step;
        let stop = match self.step_stop(at) {
            Some(stop) => {
                // walk_local plans nothing: where the way straight to the
                // goal meets what it sees, it stands (issue 54: for ever,
                // in silence).
                self.note_once(
                    "local stop",
                    &format!(
                        "walk_local stops at ({}) before what it sees on its straight way to its goal ({}); it plans no way round and stands there until its goal or behaviour changes (walk_continuously plans one)",
                        show(stop),
                        show(goal)
                    ),
                );
                stop
            }
            None => at,
        };
        self.look_at += stop - self.eye;
        self.eye = stop;
    }

    /// `auto_align` (19): turns to the `align` point, then ends.
    fn auto_align(&mut self, dt: f32) {
        let Some(p) = self.align else {
            return self.pop();
        };
        self.state = ALIGN;
        let left = self.turn_toward(p - self.eye, TURN_SPEED * dt);
        if left.abs() < 1e-4 {
            self.pop();
        }
    }

    /// The actor's voice: its sound source.
    pub fn voice(&self) -> u32 {
        ACTOR_SOURCE.saturating_add(self.id as u32)
    }

    /// `talk` (5.4): says its words one after the other, each when the
    /// one before has ended (it hears its own voice), then clears the
    /// table and ends.
    fn talk(&mut self, senses: &Senses, deeds: &mut Vec<Deed>) {
        let voice = self.voice();
        if senses.heard.iter().any(|e| e.source == voice) {
            return;
        }
        self.state = TALK;
        match self.conversation.words.first().copied() {
            Some(sound) => {
                self.conversation.words.remove(0);
                deeds.push(Deed::Say {
                    sound,
                    source: voice,
                    at: self.eye,
                });
            }
            None => self.pop(),
        }
    }

    /// `listen` (5.5): captures the next n sound events of its source
    /// (`listen_to`), in the order they begin, then ends; what it heard
    /// stays in `heard_words`.
    fn listen(&mut self, senses: &Senses) {
        let Some((source, n)) = self.conversation.listen_to else {
            return self.pop();
        };
        self.state = LISTEN_WORDS;
        let since = *self.progress.since.get_or_insert(senses.time);
        let mut new: Vec<(u32, f64)> = senses
            .heard
            .iter()
            .filter(|e| e.source == source && e.start >= since)
            .map(|e| (e.sound, e.start))
            .filter(|e| !self.progress.captured.contains(e))
            .collect();
        new.sort_by(|a, b| a.1.total_cmp(&b.1));
        self.progress.captured.extend(new);
        if self.progress.captured.len() >= n {
            self.progress.captured.truncate(n);
            self.conversation.heard_words = self.progress.captured.iter().map(|e| e.0).collect();
            self.pop();
        }
    }
}
