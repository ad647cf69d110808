//! Helpers shared by the integration tests.
#![allow(dead_code)]

use lmfilm::lsys::print::{self, Format};
use lmfilm::lsys::{Animation, NoSensors, Source};

/// A fresh, empty folder for one test: `group` keeps test files apart,
/// the process id keeps concurrent runs apart.
pub fn fresh_dir(group: &str, name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("lmfilm-{group}-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Every scene file of one form (`lm` or `lmr`) under `scenes/`, sorted,
/// so that every machine sees them in the same order.
pub fn scene_files(form: &str) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    let mut dirs = vec![std::path::PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes"
    ))];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|x| x == form) {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

pub fn example(name: &str) -> String {
    format!("{}/scenes/examples/{name}", env!("CARGO_MANIFEST_DIR"))
}

pub fn load(name: &str) -> Animation {
    Animation::load(&[example(name)], &mut NoSensors).unwrap_or_else(|e| panic!("{e}"))
}

pub fn from_text(text: &str) -> Animation {
    Animation::from_sources(&[Source::new("test.lm", text)], &mut NoSensors)
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The symbols of the first L-system's word.
pub fn symbols(a: &mut Animation) -> String {
    let (t, seed) = (a.time(), a.camera.seed);
    print::word(&mut a.systems[0], Format::Symbols, t, seed, &mut NoSensors)
}

/// The full print of the first L-system's word.
pub fn full(a: &mut Animation) -> String {
    let (t, seed) = (a.time(), a.camera.seed);
    print::word(&mut a.systems[0], Format::Full, t, seed, &mut NoSensors)
}

pub fn at_frame(a: &mut Animation, n: u64) -> String {
    a.advance_to(n, &mut NoSensors).unwrap();
    symbols(a)
}

/// The scene of the animation's current frame (surfaces loaded, no
/// particle or actor layers).
pub fn scene(a: &mut Animation) -> (lmfilm::scene::Scene, Vec<String>) {
    use lmfilm::turtle::{build_scene, NoWorld, Options, Surfaces};
    let surfaces = Surfaces::load(a).unwrap_or_else(|e| panic!("{e}"));
    build_scene(
        a,
        &surfaces,
        &mut Vec::new(),
        &mut NoWorld,
        Options::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

/// Makes the film folder `dir`'s derive record agree with frame 0's
/// snapshot as it now is, as if another program had written both: the
/// record's hash no longer catches an edit, the content checks must.
pub fn agree_with_snapshot(dir: &std::path::Path) {
    let rec = dir.join("derive.json");
    let snap = dir.join("scene/0000.snap");
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&rec).unwrap()).unwrap();
    json["snapshots"][0] =
        lmfilm::production::digest::sha256_file(&snap, lmfilm::scene::snapshot::MAX_SNAPSHOT_BYTES)
            .unwrap()
            .into();
    std::fs::write(&rec, json.to_string()).unwrap();
}

/// Counter-based xorshift: the same cases on every run, without a
/// dependency.
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// Uniform in 0..n (0 when n is 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    /// Uniform in [a, b).
    pub fn uniform(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A rayon pool whose threads' panics are recorded, not printed: a
/// fuzz test runs its cases there and reports each panic with its input.
/// The panic hook is global and other tests of the binary run at the same
/// time, so only the pool's own threads (named `name`) are recorded;
/// every other panic goes to the hook there was before, which dropping
/// the pool puts back.
pub struct PanicPool {
    pub pool: rayon::ThreadPool,
    seen: std::sync::Arc<std::sync::Mutex<Vec<String>>>,
    previous: std::sync::Arc<Hook>,
}

/// A panic hook, as `std::panic::take_hook` gives it.
type Hook = Box<dyn Fn(&std::panic::PanicHookInfo<'_>) + Sync + Send>;

impl PanicPool {
    pub fn new(name: &'static str) -> PanicPool {
        use std::sync::{Arc, Mutex};
        let seen: Arc<Mutex<Vec<String>>> = Arc::default();
        let hook_seen = Arc::clone(&seen);
        let previous = Arc::new(std::panic::take_hook());
        let others = Arc::clone(&previous);
        std::panic::set_hook(Box::new(move |info| {
            if std::thread::current().name() == Some(name) {
                hook_seen.lock().unwrap().push(info.to_string());
            } else {
                (*others)(info);
            }
        }));
        let pool = rayon::ThreadPoolBuilder::new()
            .thread_name(move |_| name.to_string())
            .build()
            .unwrap();
        PanicPool {
            pool,
            seen,
            previous,
        }
    }

    /// The message of the last panic recorded ("" when none was).
    pub fn last_panic(&self) -> String {
        self.seen.lock().unwrap().pop().unwrap_or_default()
    }
}

impl Drop for PanicPool {
    fn drop(&mut self) {
        let _ = std::panic::take_hook();
        let previous = std::sync::Arc::clone(&self.previous);
        std::panic::set_hook(Box::new(move |info| (*previous)(info)));
    }
}
