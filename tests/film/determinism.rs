//! DESIGN §4: the same inputs give the same bytes, whatever the thread
//! count or the order in which the work is done.

use std::process::Command;

fn print(threads: &str, scene: &str, args: &[&str]) -> Vec<u8> {
    let out = Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .env("RAYON_NUM_THREADS", threads)
        .arg("print")
        .arg(format!(
            "{}/scenes/examples/{scene}",
            env!("CARGO_MANIFEST_DIR")
        ))
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

#[test]
fn print_is_identical_for_any_thread_count() {
    for (scene, args) in [
        ("stochastic.lm", &["--frame", "6", "--format", "full"][..]),
        ("cours_tree3.lm", &["--time", "3", "--format", "full"][..]),
    ] {
        let one = print("1", scene, args);
        assert!(!one.is_empty());
        assert_eq!(one, print("2", scene, args), "{scene}");
        assert_eq!(one, print("2", scene, args), "{scene} rerun");
    }
}

#[test]
fn several_files_print_one_line_each() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/examples/");
    let out = Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .args([
            "print",
            &format!("{dir}timed.lm"),
            &format!("{dir}ab.lm"),
            "--frame",
            "4",
        ])
        .output()
        .unwrap();
    // The first file's Δt (1) drives both: frame 4 is T = 4 (with ab's own
    // Δt of 0.1 it would be T = 0.4, where ab prints `a`).
    assert_eq!(String::from_utf8(out.stdout).unwrap(), "S[+B]S\nb\n");
}

#[test]
fn export_is_identical_for_any_thread_count() {
    let dir = std::env::temp_dir().join(format!("lmfilm-det-{}", std::process::id()));
    let scene = format!(
        "{}/scenes/examples/cours_tree3.lm",
        env!("CARGO_MANIFEST_DIR")
    );
    let mut outputs = Vec::new();
    for threads in ["1", "2"] {
        let out = dir.join(format!("t{threads}.obj"));
        let st = Command::new(env!("CARGO_BIN_EXE_lmfilm"))
            .env("RAYON_NUM_THREADS", threads)
            .args(["export", &scene, "--time", "2", "-o", out.to_str().unwrap()])
            .status()
            .unwrap();
        assert!(st.success());
        let obj = std::fs::read_to_string(&out).unwrap();
        outputs.push(obj.replace(&format!("t{threads}.mtl"), "t.mtl"));
    }
    assert!(outputs[0].len() > 1000);
    assert_eq!(outputs[0], outputs[1]);
    std::fs::remove_dir_all(&dir).ok();
}

/// Runs lmfilm with `args` and one environment variable set to `value`.
fn lmfilm_with(var: &str, value: &str, args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .env(var, value)
        .args(args)
        .output()
        .unwrap()
}

/// Reads the file `lmfilm_with` should have written.
fn written(var: &str, value: &str, args: &[&str], file: &std::path::Path) -> Vec<u8> {
    let out = lmfilm_with(var, value, args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::read(file).unwrap()
}

/// The C library's math (glibc picks `exp`, `log`, `powf`, `sinf` … by
/// the CPU: SSE2, AVX, FMA forms) does not reach the bytes: a still and a
/// soundtrack made with the FMA and AVX forms switched off are the bytes
/// made with them (DESIGN §4: the same bytes on every x86-64 machine of
/// a farm, old or new). Where the C library is not glibc, the switch is
/// ignored and both runs are alike anyway.
#[test]
fn outputs_do_not_depend_on_the_c_librarys_math_forms() {
    let dir = std::env::temp_dir().join(format!("lmfilm-libm-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let examples = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/examples");
    let make = |tunables: &str| {
        let (png, wav) = (dir.join("still.png"), dir.join("sound.wav"));
        let gallery = format!("{examples}/gallery.lm");
        let still = ["still", &gallery, "--width", "96", "--height", "72", "-o"];
        let still = [&still[..], &[png.to_str().unwrap()]].concat();
        // The path tracer's sampling (sinf, cosf, powf) too.
        let path = [&still[..], &["--integrator", "path", "--spp", "4"]].concat();
        let events = format!("{examples}/flyby.events");
        let sound = ["sound", &events, "-o", wav.to_str().unwrap()];
        (
            written("GLIBC_TUNABLES", tunables, &still, &png),
            written("GLIBC_TUNABLES", tunables, &sound, &wav),
            written("GLIBC_TUNABLES", tunables, &path, &png),
        )
    };
    let native = make("");
    let plain = make("glibc.cpu.hwcaps=-AVX,-AVX2,-FMA,-AVX512F");
    assert!(native.0 == plain.0, "the still differs");
    assert!(native.1 == plain.1, "the soundtrack differs");
    assert!(native.2 == plain.2, "the path-traced still differs");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every SIMD path this machine has (`LMFILM_SIMD` caps the widest the
/// ray tracer takes) renders a still to the same bytes (DESIGN §4): the
/// leaves of an imported OBJ (the triangle tests, single and in packets)
/// and the gallery's shapes. A value that names no path is refused.
#[test]
fn every_simd_path_renders_the_same_still() {
    use lmfilm::render::accel::tri4::Simd;
    let dir = std::env::temp_dir().join(format!("lmfilm-simd-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let examples = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/examples");
    let png = dir.join("still.png");
    let still = |simd: &str, scene: &str, time: &str, integrator: &str| {
        let scene = format!("{examples}/{scene}");
        let args = [
            "still",
            &scene,
            "--time",
            time,
            "--width",
            "160",
            "--height",
            "120",
            "--integrator",
            integrator,
            "--spp",
            "4",
            "-o",
        ];
        let args = [&args[..], &[png.to_str().unwrap()]].concat();
        written("LMFILM_SIMD", simd, &args, &png)
    };
    for (scene, time) in [("leaves.lm", "9"), ("gallery.lm", "0")] {
        for integrator in ["whitted", "path"] {
            let base = still("baseline", scene, time, integrator);
            for simd in &Simd::available()[1..] {
                let same = still(simd.name(), scene, time, integrator) == base;
                assert!(same, "{scene}, {integrator}: {simd:?}");
            }
            // Empty is unset: the widest path.
            assert!(still("", scene, time, integrator) == base, "{scene}");
        }
    }
    std::fs::remove_file(&png).unwrap();
    let leaves = format!("{examples}/leaves.lm");
    let out = lmfilm_with(
        "LMFILM_SIMD",
        "sse2",
        &["still", &leaves, "-o", png.to_str().unwrap()],
    );
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("LMFILM_SIMD") && err.contains("avx512"),
        "{err}"
    );
    assert!(!png.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
