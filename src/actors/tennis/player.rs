//! The tennis player, `play_tennis` (thesis 5.6, figures 5.6.1–5.6.3):
//! a racket-like actor that sees the ball and its partner by colour
//! (vision), hears the collisions and the referee (audition), and keeps
//! the state of its game (`tennis_state`, table B6). Its eye is the
//! racket's centre; the racket moves along the timed spline of 5.6.6.
//!
//! The player perceives only: the ball's position from its window's
//! pixels (eq. 3.1.9), its velocity from three frames of them (eq.
//! 5.6.1), the referee's words and the ball's collisions from the sounds
//! it hears. What it does to the world is its racket's motion (its eye,
//! which `C` par1 = 5 carries into the physics) and, as the server, the
//! toss ([`Deed::Toss`]). docs/tennis.md has the readings chosen.

use glam::{DVec3, Vec3};

use super::call::word::{BLUE, EXIT, FAULT, GREEN, LEFT, LET, RIGHT, SERVICE};
use super::court::{court, service_box, side_of, Half, Player as Side, BALL_LOW, BASE_LINE};
use super::ears::Ears;
use super::eyes::{player_thing, Sightings, BALL};
use super::hit::{aim_point, hit, Aim, Hit, Shot};
use super::impact::{
    after_bounce, choose_impact, estimate_impact, horizontal, impact_delay, rising_impact,
    velocity_now, Impact, Learner,
};
use super::racket_path::{RacketPath, StrokePlan};
use crate::actors::behaviour::{is_voice, Deed, Script, Senses};
use crate::actors::live::Living;
use crate::lsys::automata::{Automata, AutomataCommand};

/// `tennis_state` values (table B6).
pub mod game {
    pub const INACTIVE: i64 = 0;
    pub const GOTO_PLAY_POSITION: i64 = 1;
    pub const LOOK_FOR_PARTNER: i64 = 2;
    pub const PARTNER_OK: i64 = 3;
    pub const FOLLOW_BALL: i64 = 4;
    pub const FIRST_HIT_TURN: i64 = 5;
    pub const HIT_TURN: i64 = 8;
    pub const BOUNCE_OR_NOT_BOUNCE: i64 = 9;
    pub const BOUNCE: i64 = 10;
    pub const BOUNCE_BEGIN: i64 = 11;
    pub const NOT_BOUNCE: i64 = 12;
    pub const HIT_PHASE: i64 = 13;
}
use game::*;

/// The collision sounds of table D.1 the player listens to.
const BALL_RACKET: u32 = 0;
const BALL_GROUND: u32 = 1;

/// Gravity the players reckon with (m/s², the scenes' `?18`).
const G: f64 = 9.81;
/// The height the racket meets the ball at (eq. 5.6.2's h), in a rally
/// and on a service (the toss is struck above the head).
const HIT_HEIGHT: f64 = 1.0;
const SERVE_HEIGHT: f64 = 2.6;
/// Eq. 5.6.1's n, and impact estimation every 4th frame (5.6.2), until
/// the ball is within 1 m of the impact point.
const VELOCITY_FRAMES: u32 = 3;
const ESTIMATE_EVERY: u64 = 4;
const STOP_ESTIMATING: f64 = 1.0;
/// The racket's stroke (5.6.6): straight for up to `HIT_LENGTH` on each
/// side of the impact, back at its start `RETURN_TIME` after it; the
/// impact is key point `MIDDLE`.
const HIT_LENGTH: f64 = 1.5;
const RETURN_TIME: f64 = 1.0;
const MIDDLE: usize = 4;
/// An elastic racket field of infinite mass sends the ball off at
/// R(v) + 2c (docs/tennis.md): the racket moves at half eq. 5.6.14's c
/// so that the ball leaves with the wished a = R(v) + c.
const FIELD_GAIN: f64 = 2.0;
/// Where the players wait: behind the base line, and on a service half
/// a metre from the centre mark (server) or in the box's middle
/// (receiver).
const BEHIND: f64 = 1.0;
const SERVER_FROM_CENTRE: f64 = 0.8;
/// The aim's margins inside the base line and the side lines: the depth
/// of the strokes scatters about 2 m, their side much less (docs/tennis.md),
/// and the service's aim, this far in front of the service line.
const AIM_DEEP: f64 = 3.5;
const AIM_WIDE: f64 = 2.0;
const SERVE_SHORT: f64 = 1.2;
/// The toss: from in front of the server, straight up.
const TOSS_AHEAD: f64 = 1.0;
const TOSS_HEIGHT: f64 = 1.2;
const TOSS_SPEED: f64 = 6.0;
/// A server that has not struck its toss this long after tosses again.
const TOSS_PATIENCE: f64 = 2.5;
/// A server waits this long once ready, and looks for its partner at
/// most `PARTNER_PATIENCE` before it plays anyway.
const SERVE_PAUSE: f64 = 0.6;
const PARTNER_PATIENCE: f64 = 3.0;
/// A partner within this of its start point is ready (look_for_partner).
const PARTNER_NEAR: f64 = 2.5;
/// The ball's diameter as the players know it, and how many pixels wide
/// their search makes it.
const BALL_SIZE: f64 = 0.2;
const SEARCH_PIXELS: f64 = 3.0;
/// How far from its start a player goes for the ball (horizontally).
const REACH: f64 = 8.0;
/// Below this height the ball is about to bounce (bounce_begin).
const BOUNCE_BEGINS: f64 = 0.5;
/// A ball landing this far outside the player's court is let go.
const LET_GO: f64 = 1.0;

/// What vision is busy with (figure 5.6.3): the ball, or a glance at the
/// partner.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Focus {
    Thing,
    Partner,
}

/// A planned stroke.
#[derive(Debug, Clone)]
struct Stroke {
    impact: Impact,
    path: RacketPath,
    /// The aim it was planned for, the ball's wished velocity, and
    /// whether it is a service.
    aim: DVec3,
    wished: DVec3,
    serve: bool,
}

/// What a player keeps between frames.
#[derive(Debug, Clone)]
pub struct Player {
    pub side: Side,
    /// Where it waits for the ball, and where its partner does.
    pub start: DVec3,
    opponent_start: DVec3,
    /// The server of the point in play.
    server: Option<Side>,
    /// `interpret_words`: `listen` is capturing the server and its half.
    interpret: bool,
    focus: Focus,
    /// Since when it looks for its partner, and since when it is ready.
    looking_since: Option<f64>,
    ready_since: Option<f64>,
    ball: Sightings,
    /// Eq. 5.6.1's velocity, derived every third frame.
    velocity: Option<DVec3>,
    frames: u64,
    learner: Learner,
    rally: Aim,
    service: Aim,
    aim: DVec3,
    stroke: Option<Stroke>,
    /// Where the ball was, how fast, when entering bounce_or_not_bounce
    /// (eq. 5.6.6's P₁, v, t₁).
    first_sight: Option<(DVec3, DVec3, f64)>,
    /// Its last stroke, until it learns where the ball landed.
    shot: Option<(Shot, bool)>,
    /// The ball as its last stroke sent it: from where, when, how fast
    /// (the wished velocity a): where its eyes look for it.
    sent: Option<(DVec3, f64, DVec3)>,
    ears: Ears,
    /// Where and when it tossed the ball for its service.
    tossed: Option<(DVec3, f64)>,
    /// Its strokes in the point: the first is a service or a return.
    strokes: u32,
    /// When the ball bounced on its side since the last stroke heard.
    bounced: Option<f64>,
    /// Whether the partner's stroke was heard since its own.
    partner_struck: bool,
    /// The ball's side of the net at the last sighting.
    ball_side: Option<Side>,
}

impl Player {
    fn new(side: Side) -> Self {
        let start = rally_spot(side);
        Player {
            side,
            start,
            opponent_start: rally_spot(side.opponent()),
            server: None,
            interpret: false,
            focus: Focus::Thing,
            looking_since: None,
            ready_since: None,
            ball: Sightings::default(),
            velocity: None,
            frames: 0,
            learner: Learner::default(),
            rally: Aim {
                c1: 5.0,
                c2: 0.75,
                inclination: 0.25,
            },
            service: Aim {
                c1: 5.0,
                c2: 0.92,
                inclination: 0.05,
            },
            aim: aim_point(rally_spot(side.opponent()), AIM_DEEP, AIM_WIDE),
            stroke: None,
            first_sight: None,
            shot: None,
            sent: None,
            ears: Ears::default(),
            tossed: None,
            strokes: 0,
            bounced: None,
            partner_struck: false,
            ball_side: None,
        }
    }

    fn is_server(&self) -> bool {
        self.server == Some(self.side)
    }

    /// The point is over: no stroke is pending any more.
    fn end_point(&mut self) {
        self.server = None;
        self.tossed = None;
        self.strokes = 0;
        self.stroke = None;
        self.bounced = None;
        self.sent = None;
        self.partner_struck = false;
        self.first_sight = None;
        self.ready_since = None;
        self.looking_since = None;
    }
}

/// The sign of x on a side of the net.
fn x_sign(side: Side) -> f64 {
    match side {
        Side::Green => -1.0,
        Side::Blue => 1.0,
    }
}

/// Where a player waits in a rally: behind the middle of its base line,
/// at the hitting height.
fn rally_spot(side: Side) -> DVec3 {
    DVec3::new(x_sign(side) * (BASE_LINE + BEHIND), HIT_HEIGHT, 0.0)
}

/// Where the server stands (next to the centre mark, on the half it
/// serves from) and where the receiver waits (behind the box's middle).
fn service_spots(server: Side, half: Half) -> [DVec3; 2] {
    let target = service_box(server, half);
    let box_z = 0.5 * (target.z[0] + target.z[1]);
    // The server stands diagonally opposite the box's middle.
    let server_z = -box_z.signum() * SERVER_FROM_CENTRE;
    [
        DVec3::new(x_sign(server) * (BASE_LINE + BEHIND), HIT_HEIGHT, server_z),
        DVec3::new(-x_sign(server) * (BASE_LINE + BEHIND), HIT_HEIGHT, box_z),
    ]
}

/// The service's aim: the middle of the box, `SERVE_SHORT` before its
/// service line.
fn service_aim(server: Side, half: Half) -> DVec3 {
    let b = service_box(server, half);
    let far = if b.x[1].abs() > b.x[0].abs() {
        b.x[1]
    } else {
        b.x[0]
    };
    DVec3::new(
        far - SERVE_SHORT * far.signum(),
        0.0,
        0.5 * (b.z[0] + b.z[1]),
    )
}

/// The ball's velocity at the impact, predicted without air damping:
/// the same horizontal run, gravity on the vertical part.
fn velocity_at(v: DVec3, now: f64, impact: &Impact) -> DVec3 {
    DVec3::new(v.x, v.y - G * (impact.time - now), v.z)
}

impl Living {
    /// `play_tennis` (5.6): audition, then vision, then the game, then
    /// the racket's motion, each frame.
    pub(in crate::actors) fn play_tennis(&mut self, senses: &Senses, deeds: &mut Vec<Deed>) {
        if self.player.is_none() {
            let side = if self.id == 0 {
                Side::Green
            } else {
                Side::Blue
            };
            self.player = Some(Player::new(side));
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
        let p = self.player.as_mut().expect("playing");
        if std::mem::take(&mut p.interpret) {
            // interpret_words: the server's name and its half.
            if let [name, half] = self.heard_words[..] {
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
                    if self.tennis_state > FOLLOW_BALL {
                        self.tennis_state = FOLLOW_BALL;
                    }
                }
                SERVICE if voice => {
                    p.end_point();
                    p.interpret = true;
                    self.listen_to = Some((e.source, 2));
                    self.push(Script::of(Automata::PlayTennis));
                    self.activate(Script::of(Automata::Listen));
                    return true;
                }
                EXIT if voice => {
                    p.end_point();
                    self.tennis_state = INACTIVE;
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
        let p = self.player.as_mut().expect("playing");
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
        self.tennis_state = GOTO_PLAY_POSITION;
        self.push(Script {
            automata: Automata::PlayTennis,
            commands: vec![AutomataCommand::TennisState(GOTO_PLAY_POSITION)],
        });
        self.goals.push(mine.as_vec3());
        self.activate(Script::of(Automata::WalkContinuously));
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
        let p = self.player.as_ref().expect("playing");
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
        let p = self.player.as_mut().expect("playing");
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
                    self.tennis_state = PARTNER_OK;
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
        let p = self.player.as_ref().expect("playing");
        if p.focus == Focus::Partner || self.tennis_state == LOOK_FOR_PARTNER {
            player_thing(p.side.opponent().index())
        } else {
            BALL
        }
    }

    /// The game's Petri net (figure 5.6.1).
    fn play(&mut self, senses: &Senses, deeds: &mut Vec<Deed>) {
        let t = senses.time;
        let p = self.player.as_mut().expect("playing");
        let striking = self.tennis_state == HIT_PHASE;
        if self.tennis_state > FOLLOW_BALL && !striking && p.gone() {
            // The ball went past or away: it waits for the next one.
            p.stroke = None;
            self.tennis_state = FOLLOW_BALL;
        }
        let missed = p.tossed.is_some_and(|(_, at)| t - at > TOSS_PATIENCE);
        if missed && p.strokes == 0 && self.tennis_state > FOLLOW_BALL {
            // It missed its toss: it tosses again.
            p.tossed = None;
            p.stroke = None;
            self.tennis_state = FOLLOW_BALL;
        }
        match self.tennis_state {
            INACTIVE | GOTO_PLAY_POSITION => {
                let to = p.start.as_vec3();
                let step = self.speed * senses.dt as f32;
                let left = to - self.eye;
                if left.length() <= step.max(1e-3) {
                    self.eye = to;
                    self.tennis_state = LOOK_FOR_PARTNER;
                    p.looking_since = Some(t);
                } else {
                    self.eye += left.normalize() * step;
                }
            }
            LOOK_FOR_PARTNER => {
                let since = *p.looking_since.get_or_insert(t);
                if t - since > PARTNER_PATIENCE {
                    self.tennis_state = PARTNER_OK;
                }
            }
            PARTNER_OK => {
                self.tennis_state = FOLLOW_BALL;
                p.ready_since = Some(t);
                self.look_around_set();
            }
            FOLLOW_BALL => {
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
                        self.tennis_state = NOT_BOUNCE;
                    }
                    return;
                }
                if p.server.is_some() && p.coming() {
                    self.tennis_state = FIRST_HIT_TURN;
                }
            }
            FIRST_HIT_TURN..=7 => self.tennis_state += 1,
            HIT_TURN => self.tennis_state = BOUNCE_OR_NOT_BOUNCE,
            BOUNCE_OR_NOT_BOUNCE => {
                let Some(v) = p.velocity else { return };
                let Some((_, at)) = p.ball.last() else { return };
                if p.bounced.is_some() {
                    // It bounced already: it is taken on the rise.
                    self.tennis_state = NOT_BOUNCE;
                    return;
                }
                let serving = p.is_server() && p.strokes == 0;
                let h = if serving { SERVE_HEIGHT } else { HIT_HEIGHT };
                let Some(first) = estimate_impact(at, v, t, h, G, p.learner.x()) else {
                    return;
                };
                if !serving && p.bounced.is_none() && !p.side_ok(at, v, t) {
                    // It lands out: let it go, and wait for the call.
                    self.tennis_state = FOLLOW_BALL;
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
                self.tennis_state = if bounce { BOUNCE } else { NOT_BOUNCE };
                let eye = self.eye.as_dvec3();
                let v_imp = if bounce {
                    let at_bounce = velocity_at(v, t, &first);
                    DVec3::new(at_bounce.x, -at_bounce.y, at_bounce.z)
                } else {
                    velocity_at(v, t, &choice.impact)
                };
                p.plan(eye, t, choice.impact, v_imp, serving);
            }
            BOUNCE => {
                let Some((_, at)) = p.ball.last() else { return };
                if at.y < BOUNCE_BEGINS || p.bounced.is_some() {
                    self.tennis_state = BOUNCE_BEGIN;
                    p.learn_x(at, t);
                    return;
                }
                let far = !p
                    .stroke
                    .as_ref()
                    .is_some_and(|s| at.distance(s.impact.point) <= STOP_ESTIMATING);
                if let (true, Some(v)) =
                    (far && p.frames.is_multiple_of(ESTIMATE_EVERY), p.velocity)
                {
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
            BOUNCE_BEGIN => {
                // The ball has hit the ground (heard) and climbs again.
                if p.bounced.is_some() {
                    self.tennis_state = NOT_BOUNCE;
                    p.velocity = None;
                }
            }
            NOT_BOUNCE => {
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
                if s.impact.time - t <= 2.0 * senses.dt {
                    self.tennis_state = HIT_PHASE;
                    if let Some((_, at)) = p.ball.last() {
                        p.learn_x(at, t);
                    }
                }
            }
            HIT_PHASE => {
                let Some(s) = &p.stroke else {
                    self.tennis_state = FOLLOW_BALL;
                    return;
                };
                if t > s.impact.time + senses.dt {
                    p.shot = Some((Shot::new(s.impact.point, s.aim), s.serve));
                    p.sent = Some((s.impact.point, s.impact.time, s.wished));
                    p.strokes += 1;
                    p.partner_struck = false;
                    self.tennis_state = FOLLOW_BALL;
                    p.velocity = None;
                }
            }
            _ => self.tennis_state = GOTO_PLAY_POSITION,
        }
    }

    /// The racket follows its planned path: where it is next frame is
    /// where the next frame's interpretation places its particle.
    fn swing(&mut self, senses: &Senses) {
        let p = self.player.as_mut().expect("playing");
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
        let s = self.player.as_ref()?.stroke.as_ref()?;
        let n = s.path.normal(t);
        (n != DVec3::ZERO).then(|| n.as_vec3())
    }
}

impl Player {
    /// Whether the ball flies toward it, from the net's side of it,
    /// since it heard its partner strike.
    fn coming(&self) -> bool {
        let sign = x_sign(self.side);
        if !self.partner_struck {
            return false;
        }
        let ahead = self
            .ball
            .last()
            .is_some_and(|(_, b)| b.x * sign < self.start.x * sign);
        ahead && self.velocity.is_some_and(|v| v.x * sign > 1.0)
    }

    /// Whether the ball has gone: past it beyond its reach, or flying
    /// back over the net (not its own toss).
    fn gone(&self) -> bool {
        let sign = x_sign(self.side);
        let Some((_, b)) = self.ball.last() else {
            return false;
        };
        let past = b.x * sign > self.start.x * sign + REACH;
        let back = self.velocity.is_some_and(|v| v.x * sign < -1.0) && b.x * sign < 0.0;
        past || back
    }

    /// Eq. 5.6.6: learns x from the first sighting and this one.
    fn learn_x(&mut self, at: DVec3, t: f64) {
        if let Some((p1, v1, t1)) = self.first_sight.take() {
            self.learner.learn(p1, v1, t1, at, t);
        }
    }

    /// Whether a ball seen at `at` with velocity `v` at `t` lands in
    /// the player's court (a margin outside counts in).
    fn side_ok(&self, at: DVec3, v: DVec3, t: f64) -> bool {
        let Some(landing) = estimate_impact(at, v, t, 0.0, G, 1.0) else {
            return true;
        };
        let c = court(self.side);
        let l = landing.point;
        let inside = |x: f64, r: [f64; 2]| x >= r[0] - LET_GO && x <= r[1] + LET_GO;
        inside(l.x, c.x) && inside(l.z, c.z)
    }

    /// Plans the stroke at `impact` (5.6.4–5.6.6): the wished velocity
    /// toward the aim, the racket's velocity, its timed path.
    fn plan(&mut self, racket: DVec3, now: f64, impact: Impact, v: DVec3, serve: bool) {
        if horizontal(impact.point - self.start).length() > REACH {
            // Out of its reach: it keeps the plan it has, if any.
            return;
        }
        let aim = if serve { &self.service } else { &self.rally };
        let a = aim.velocity(impact.point, self.aim);
        let Hit { normal, speed } = hit(v, a);
        let velocity = self
            .stroke
            .as_ref()
            .map_or(DVec3::ZERO, |s| s.path.at(now).1);
        let plan = StrokePlan {
            now,
            position: racket,
            velocity,
            impact,
            hit: Hit {
                normal,
                speed: speed / FIELD_GAIN,
            },
            hit_length: HIT_LENGTH,
            return_time: RETURN_TIME,
            start: self.start,
            opponent_start: self.opponent_start,
            middle: MIDDLE,
        };
        if let Some(path) = RacketPath::plan(&plan) {
            self.stroke = Some(Stroke {
                impact,
                path,
                aim: self.aim,
                wished: a,
                serve,
            });
        }
    }
}
