//! `play_tennis` (thesis 5.6) as the actor runs it, over the player
//! state of the parent module.

use super::*;
use crate::actors::live::Living;

impl Living {
    /// `play_tennis` (5.6): audition, then vision, then the game, then
    /// the racket's motion, each frame.
    pub(in crate::actors) fn play_tennis(&mut self, senses: &Senses, deeds: &mut Vec<Deed>) {
        if self.tennis.player.is_none() {
            let side = if self.id == 0 {
                Side::Green
            } else {
                Side::Blue
            };
            self.tennis.player = Some(Player::new(side));
            // It runs to its place on an open court (walk_continuously).
            self.navigation.tuning.open_court = true;
        }
        if self.hear(senses) {
            return;
        }
        self.see(senses);
        self.play(senses, deeds);
        self.swing(senses);
    }

    /// The audition of figure 5.6.3; true when it handed over to another
    /// automata.
    fn hear(&mut self, senses: &Senses) -> bool {
        let me = self.voice();
        let p = self.tennis.player.as_mut().expect("playing");
        if std::mem::take(&mut p.interpret) {
            // interpret_words: the server's name and its half.
            if let [name, half] = self.conversation.heard_words[..] {
                return self.begin_point(name, half);
            }
        }
        for e in p.ears.news(senses.heard) {
            if e.source == me {
                continue;
            }
            let voice = is_voice(e.source);
            match e.sound {
                // The point is over: the ball is dead, and the next
                // service says where to go.
                FAULT | LET if voice => {
                    p.end_point();
                    if self.tennis.state > FOLLOW_BALL {
                        self.tennis.state = FOLLOW_BALL;
                    }
                }
                SERVICE if voice => {
                    p.end_point();
                    p.interpret = true;
                    self.conversation.listen_to = Some((e.source, 2));
                    self.push(Behaviour::of(Automata::PlayTennis));
                    self.activate(Behaviour::of(Automata::Listen));
                    return true;
                }
                EXIT if voice => {
                    p.end_point();
                    self.tennis.state = INACTIVE;
                    self.pop();
                    return true;
                }
                BALL_GROUND | BALL_RACKET if !voice => {
                    let partner = side_of([e.position.x, e.position.z]) != p.side;
                    match e.sound {
                        BALL_GROUND if !partner => p.bounced = Some(e.start),
                        BALL_RACKET => {
                            p.bounced = None;
                            if partner {
                                p.sent = None;
                                p.partner_struck = true;
                            }
                        }
                        _ => {}
                    }
                    // Where: seen, else where the sound came from.
                    let seen = p.ball.at(e.start).or(Some(e.position));
                    // Where its last stroke landed (5.6.4): its first
                    // bounce on the partner's side teaches c2. A bounce on
                    // its own side (a mishit) or the partner's racket (a
                    // volley, short of where the ball would have landed)
                    // says nothing of its stroke's length: that shot is
                    // forgotten, not learnt from.
                    let ends_shot = e.sound == BALL_GROUND || partner;
                    if let Some((shot, serve)) = p.shot.filter(|_| ends_shot) {
                        p.shot = None;
                        if e.sound == BALL_GROUND && partner {
                            if let Some(at) = seen {
                                let aim = if serve { &mut p.service } else { &mut p.rally };
                                aim.learn(&shot, at);
                            }
                        }
                    }
                }
                _ => {}
            }
        }
        false
    }

    /// The referee named the server and its half: both players walk to
    /// their places (walk_continuously), then play the point.
    fn begin_point(&mut self, name: u32, half: u32) -> bool {
        let p = self.tennis.player.as_mut().expect("playing");
        let server = match name {
            GREEN => Side::Green,
            BLUE => Side::Blue,
            _ => return false,
        };
        let half = match half {
            RIGHT => Half::Right,
            LEFT => Half::Left,
            _ => return false,
        };
        let spots = service_spots(server, half);
        let (mine, theirs) = if server == p.side {
            (spots[0], spots[1])
        } else {
            (spots[1], spots[0])
        };
        p.server = Some(server);
        p.start = mine;
        p.opponent_start = theirs;
        p.aim = if server == p.side {
            service_aim(server, half)
        } else {
            aim_point(theirs, AIM_DEEP, AIM_WIDE)
        };
        p.stroke = None;
        self.tennis.state = GOTO_PLAY_POSITION;
        self.push(Behaviour {
            automata: Automata::PlayTennis,
            commands: vec![AutomataCommand::TennisState(GOTO_PLAY_POSITION)],
        });
        self.goals.push(mine.as_vec3());
        self.activate(Behaviour::of(Automata::WalkContinuously));
        true
    }

    /// Vision (5.6.1): follows the ball, or glances at its partner.
    fn see(&mut self, senses: &Senses) {
        let sensed = self.interest;
        self.interest = Some(self.wanted_interest());
        if sensed != self.interest {
            // The window was made for another thing: it looks next frame.
            return;
        }
        let p = self.tennis.player.as_ref().expect("playing");
        let partner = player_thing(p.side.opponent().index());
        if self.interest == Some(partner) && self.percepts.as_ref().and_then(|w| w.thing).is_none()
        {
            // The partner is looked for where it should stand.
            let at = p.opponent_start.as_vec3();
            self.look_at = at;
        }
        let lead = if self.interest == Some(BALL) {
            p.ball.lead(senses.dt)
        } else {
            Vec3::ZERO
        };
        let found = self.follow_thing(lead);
        let p = self.tennis.player.as_mut().expect("playing");
        if found.is_none() && self.interest == Some(BALL) {
            // look_around_set (5.6.1): where the ball should be — on its
            // way from its last sightings, else by the partner — with a
            // view angle that makes a ball there a few pixels wide.
            let next = senses.time + senses.dt;
            let toss = p.tossed.filter(|_| p.strokes == 0).map(|(at, _)| at);
            // Where its stroke sent the ball, gravity pulling it down.
            let sent = p.sent.map(|(from, t0, a)| {
                let dt = next - t0;
                from + a * dt - DVec3::Y * (0.5 * G * dt * dt)
            });
            let at = (p.ball.at(next))
                .or(sent.filter(|s| s.y > 0.0))
                .or(toss)
                .unwrap_or(p.opponent_start);
            let distance = at.distance(self.eye.as_dvec3()).max(1.0);
            let angle = 2.0 * (0.5 * BALL_SIZE / distance).atan().to_degrees();
            let edge = f64::from(self.edge.unwrap_or(1));
            let fov = (angle * edge / SEARCH_PIXELS * 10.0) as i64;
            self.look_at = at.as_vec3();
            self.fov = fov.clamp(20, 600);
        }
        match (found, self.interest == Some(BALL)) {
            (Some(ball), true) => {
                p.ball.push(senses.time, ball.position);
                p.frames += 1;
                if p.frames.is_multiple_of(u64::from(VELOCITY_FRAMES)) {
                    let window = f64::from(VELOCITY_FRAMES) * senses.dt;
                    // A window across the bounce would mix two paths.
                    let across = p.bounced.is_some_and(|b| b > senses.time - window);
                    p.velocity = (!across)
                        .then(|| p.ball.velocity(VELOCITY_FRAMES, senses.dt))
                        .flatten()
                        .map(|v| velocity_now(v, window, G));
                }
                let side = side_of([f64::from(ball.position.x), f64::from(ball.position.z)]);
                // The ball crosses the net away from it: a glance at the
                // partner, for the aim of the next stroke (5.6.4).
                if p.ball_side == Some(p.side) && side != p.side {
                    p.focus = Focus::Partner;
                }
                p.ball_side = Some(side);
            }
            (Some(partner), false) => {
                if p.focus == Focus::Partner {
                    p.aim = aim_point(partner.position.as_dvec3(), AIM_DEEP, AIM_WIDE);
                    p.focus = Focus::Thing;
                } else if partner.position.as_dvec3().distance(p.opponent_start) < PARTNER_NEAR {
                    self.tennis.state = PARTNER_OK;
                }
            }
            (None, _) => {
                if p.focus == Focus::Partner {
                    // A glance lasts one frame.
                    p.focus = Focus::Thing;
                }
            }
        }
        self.interest = Some(self.wanted_interest());
    }

    /// What vision looks for: the partner while it waits for it or
    /// glances at it, else the ball.
    fn wanted_interest(&self) -> i64 {
        let p = self.tennis.player.as_ref().expect("playing");
        if p.focus == Focus::Partner || self.tennis.state == LOOK_FOR_PARTNER {
            player_thing(p.side.opponent().index())
        } else {
            BALL
        }
    }

    /// The game's Petri net (figure 5.6.1).
    fn play(&mut self, senses: &Senses, deeds: &mut Vec<Deed>) {
        let t = senses.time;
        let p = self.tennis.player.as_mut().expect("playing");
        let striking = self.tennis.state == HIT_PHASE;
        if self.tennis.state > FOLLOW_BALL && !striking && p.gone() {
            // The ball went past or away: it waits for the next one.
            p.stroke = None;
            self.tennis.state = FOLLOW_BALL;
        }
        let missed = p.tossed.is_some_and(|(_, at)| t - at > TOSS_PATIENCE);
        if missed && p.strokes == 0 && self.tennis.state > FOLLOW_BALL {
            // It missed its toss: it tosses again.
            p.tossed = None;
            p.stroke = None;
            self.tennis.state = FOLLOW_BALL;
        }
        match self.tennis.state {
            INACTIVE | GOTO_PLAY_POSITION => {
                let to = p.start.as_vec3();
                let step = self.speed * senses.dt as f32;
                let left = to - self.eye;
                if left.length() <= step.max(1e-3) {
                    self.eye = to;
                    self.tennis.state = LOOK_FOR_PARTNER;
                    p.looking_since = Some(t);
                } else {
                    self.eye += left.normalize() * step;
                }
            }
            LOOK_FOR_PARTNER => {
                let since = *p.looking_since.get_or_insert(t);
                if t - since > PARTNER_PATIENCE {
                    self.tennis.state = PARTNER_OK;
                }
            }
            PARTNER_OK => {
                self.tennis.state = FOLLOW_BALL;
                p.ready_since = Some(t);
                self.look_around_set();
            }
            FOLLOW_BALL => self.follow_ball(t, deeds),
            FIRST_HIT_TURN..=7 => self.tennis.state += 1,
            HIT_TURN => self.tennis.state = BOUNCE_OR_NOT_BOUNCE,
            BOUNCE_OR_NOT_BOUNCE => self.bounce_or_not(t),
            BOUNCE => self.before_bounce(t),
            BOUNCE_BEGIN => {
                // The ball has hit the ground (heard) and climbs again.
                if p.bounced.is_some() {
                    self.tennis.state = NOT_BOUNCE;
                    p.velocity = None;
                }
            }
            NOT_BOUNCE => self.before_impact(t, senses.dt),
            HIT_PHASE => self.hit_phase(t, senses.dt),
            _ => self.tennis.state = GOTO_PLAY_POSITION,
        }
    }

    /// Follows the ball; the server tosses once it has waited its pause, and knows its toss's impact.
    fn follow_ball(&mut self, t: f64, deeds: &mut Vec<Deed>) {
        let p = self.tennis.player.as_mut().expect("playing");
        if p.is_server() && p.tossed.is_none() {
            let ready = *p.ready_since.get_or_insert(t);
            if t - ready >= SERVE_PAUSE {
                let ahead = DVec3::X * -x_sign(p.side) * TOSS_AHEAD;
                let at = DVec3::new(p.start.x, TOSS_HEIGHT, p.start.z) + ahead;
                deeds.push(Deed::Toss {
                    at: at.as_vec3(),
                    velocity: Vec3::Y * TOSS_SPEED as f32,
                });
                p.tossed = Some((at, t));
                p.velocity = None;
                p.ball.clear();
                self.look_at = at.as_vec3();
                // It knows its toss: the ball falls back through
                // the service height then.
                let up = TOSS_SPEED;
                if let Some(delay) = impact_delay(TOSS_HEIGHT, up, SERVE_HEIGHT, G) {
                    let impact = Impact {
                        point: DVec3::new(at.x, SERVE_HEIGHT, at.z),
                        time: t + delay,
                    };
                    let v = DVec3::Y * (up - G * delay);
                    let eye = self.eye.as_dvec3();
                    p.plan(eye, t, impact, v, true);
                }
                self.tennis.state = NOT_BOUNCE;
            }
            return;
        }
        if p.server.is_some() && p.coming() {
            self.tennis.state = FIRST_HIT_TURN;
        }
    }

    /// Decides, from the first sight of the coming ball, whether it takes it after its bounce or before (eq. 5.6.7), and plans the stroke.
    fn bounce_or_not(&mut self, t: f64) {
        let p = self.tennis.player.as_mut().expect("playing");
        let Some(v) = p.velocity else { return };
        let Some((_, at)) = p.ball.last() else { return };
        if p.bounced.is_some() {
            // It bounced already: it is taken on the rise.
            self.tennis.state = NOT_BOUNCE;
            return;
        }
        let serving = p.is_server() && p.strokes == 0;
        let h = if serving { SERVE_HEIGHT } else { HIT_HEIGHT };
        let Some(first) = estimate_impact(at, v, t, h, G, p.learner.x()) else {
            return;
        };
        if !serving && p.bounced.is_none() && !p.side_ok(at, v, t) {
            // It lands out: let it go, and wait for the call.
            self.tennis.state = FOLLOW_BALL;
            p.velocity = None;
            return;
        }
        p.first_sight = Some((at, v, t));
        p.stroke = None;
        // The receiver lets a service bounce (a volley would lose
        // the point).
        let receiving = !p.is_server() && p.strokes == 0 && p.bounced.is_none();
        // Eq. 5.6.7 with the ball's velocity as it falls through h.
        let second = after_bounce(&first, velocity_at(v, t, &first), h, BALL_LOW, G);
        let choice = if serving {
            choose_impact(p.start, first, None)
        } else if receiving {
            match second {
                Some(s) => choose_impact(p.start, s, None),
                None => return,
            }
        } else {
            choose_impact(p.start, first, second)
        };
        let bounce = receiving || (choice.bounce && !serving);
        self.tennis.state = if bounce { BOUNCE } else { NOT_BOUNCE };
        let eye = self.eye.as_dvec3();
        let v_imp = if bounce {
            let at_bounce = velocity_at(v, t, &first);
            DVec3::new(at_bounce.x, -at_bounce.y, at_bounce.z)
        } else {
            velocity_at(v, t, &choice.impact)
        };
        p.plan(eye, t, choice.impact, v_imp, serving);
    }

    /// Waits for the bounce, estimating the impact after it again while the ball is far.
    fn before_bounce(&mut self, t: f64) {
        let p = self.tennis.player.as_mut().expect("playing");
        let Some((_, at)) = p.ball.last() else { return };
        if at.y < BOUNCE_BEGINS || p.bounced.is_some() {
            self.tennis.state = BOUNCE_BEGIN;
            p.learn_x(at, t);
            return;
        }
        let far = !p
            .stroke
            .as_ref()
            .is_some_and(|s| at.distance(s.impact.point) <= STOP_ESTIMATING);
        if let (true, Some(v)) = (far && p.frames.is_multiple_of(ESTIMATE_EVERY), p.velocity) {
            let first = estimate_impact(at, v, t, HIT_HEIGHT, G, p.learner.x());
            let second = first.and_then(|f| {
                let fall = velocity_at(v, t, &f);
                Some((after_bounce(&f, fall, HIT_HEIGHT, BALL_LOW, G)?, fall))
            });
            if let Some((second, fall)) = second {
                let eye = self.eye.as_dvec3();
                let rebound = DVec3::new(fall.x, fall.y.abs(), fall.z);
                p.plan(eye, t, second, rebound, false);
            }
        }
    }

    /// Estimates the impact again while the ball is far, and starts the hit phase two frames before it.
    fn before_impact(&mut self, t: f64, dt: f64) {
        let p = self.tennis.player.as_mut().expect("playing");
        let serving = p.stroke.as_ref().is_some_and(|s| s.serve);
        let close = |p: &Player| match (&p.stroke, p.ball.last()) {
            (Some(s), Some((_, b))) => b.distance(s.impact.point) < STOP_ESTIMATING,
            _ => false,
        };
        let estimate = !serving && !close(p) && p.frames.is_multiple_of(ESTIMATE_EVERY);
        if p.stroke.is_none() || estimate {
            if let (Some(v), Some((_, at))) = (p.velocity, p.ball.last()) {
                let h = if serving { SERVE_HEIGHT } else { HIT_HEIGHT };
                let x = p.learner.x();
                // After the bounce the ball is taken on the rise.
                let impact = match p.bounced {
                    Some(_) => rising_impact(at, v, t, h, G, x),
                    None => estimate_impact(at, v, t, h, G, x),
                };
                if let Some(i) = impact {
                    let eye = self.eye.as_dvec3();
                    p.plan(eye, t, i, velocity_at(v, t, &i), serving);
                }
            }
        }
        let Some(s) = &p.stroke else { return };
        if s.impact.time - t <= 2.0 * dt {
            self.tennis.state = HIT_PHASE;
            if let Some((_, at)) = p.ball.last() {
                p.learn_x(at, t);
            }
        }
    }

    /// The stroke: once its impact time is past, the shot is sent.
    fn hit_phase(&mut self, t: f64, dt: f64) {
        let p = self.tennis.player.as_mut().expect("playing");
        let Some(s) = &p.stroke else {
            self.tennis.state = FOLLOW_BALL;
            return;
        };
        if t > s.impact.time + dt {
            p.shot = Some((Shot::new(s.impact.point, s.aim), s.serve));
            p.sent = Some((s.impact.point, s.impact.time, s.wished));
            p.strokes += 1;
            p.partner_struck = false;
            self.tennis.state = FOLLOW_BALL;
            p.velocity = None;
        }
    }

    /// The racket follows its planned path: where it is next frame is
    /// where the next frame's interpretation places its particle.
    fn swing(&mut self, senses: &Senses) {
        let p = self.tennis.player.as_mut().expect("playing");
        let Some(s) = &p.stroke else { return };
        let next = senses.time + senses.dt;
        self.eye = s.path.at(next).0.as_vec3();
        if next >= s.path.end() {
            p.stroke = None;
        }
    }

    /// The direction the racket faces: its motion along the planned path
    /// (turtle 2), when it has one.
    pub fn racket_normal(&self, t: f64) -> Option<Vec3> {
        let s = self.tennis.player.as_ref()?.stroke.as_ref()?;
        let n = s.path.normal(t);
        (n != DVec3::ZERO).then(|| n.as_vec3())
    }
}
