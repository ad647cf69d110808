//! The parallel OBJ parser: what tobj read before, across chunk borders,
//! with line numbers in errors and the same result for any thread count.

use glam::Vec3;
use lmfilm::scene::obj_parse::{parse, Obj};

fn pool(n: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .unwrap()
}

#[test]
fn faces_polygons_negative_indices_and_materials() {
    let text = "mtllib a b.mtl\nv 0 0 0\nv 1 0 0 # comment\nv 1 1 0\nv 0 1 0 1.0\nvn 0 0 1\nvt 0 0\n\
                usemtl red\nf 1/1/1 2//1 3\ng part\nusemtl blue\nf -4 -3 -2 -1\nl 1 2\nf 1 2 \\\n 4\n";
    let obj = parse(text.as_bytes()).unwrap();
    assert_eq!(obj.positions.len(), 4);
    assert_eq!(obj.positions[3], Vec3::new(0.0, 1.0, 0.0));
    assert_eq!(obj.libraries, ["a b.mtl"]);
    assert_eq!(obj.materials, ["red", "blue"]);
    assert_eq!(
        obj.triangles,
        [
            ([0, 1, 2], Some(0)),
            ([0, 1, 2], Some(1)),
            ([0, 2, 3], Some(1)),
            ([0, 1, 3], Some(1)),
        ]
    );
}

/// A file several chunks long: a usemtl just before a chunk border, and
/// negative indices counting across it.
fn big_file() -> (String, usize) {
    let mut s = String::new();
    let mut faces = 0;
    let mut k = 0;
    while s.len() < 3_500_000 {
        s.push_str(&format!("v {k} 0.5 -1.25\nv {k} 1 0\nv {k} 0 1\n"));
        if k % 1000 == 0 {
            s.push_str(&format!("usemtl m{}\n", k % 3));
        }
        s.push_str("f -3 -2 -1\n");
        faces += 1;
        k += 1;
    }
    (s, faces)
}

#[test]
fn chunks_join_like_one_pass_for_any_thread_count() {
    let (text, faces) = big_file();
    let one: Obj = pool(1).install(|| parse(text.as_bytes()).unwrap());
    let two: Obj = pool(2).install(|| parse(text.as_bytes()).unwrap());
    assert_eq!(one, two);
    assert_eq!(one.triangles.len(), faces);
    assert_eq!(one.materials, ["m0", "m1", "m2"]);
    for (k, (v, m)) in one.triangles.iter().enumerate() {
        let b = 3 * k as u32;
        assert_eq!(*v, [b, b + 1, b + 2]);
        assert_eq!(*m, Some(((k / 1000) % 3) as u32), "face {k}");
        assert_eq!(one.positions[b as usize], Vec3::new(k as f32, 0.5, -1.25));
    }
}

#[test]
fn errors_name_the_line_even_late_in_the_file() {
    let (mut text, _) = big_file();
    let lines = text.lines().count();
    text.push_str("v 1 2 x\n");
    let err = parse(text.as_bytes()).unwrap_err().to_string();
    assert!(err.starts_with(&format!("line {}:", lines + 1)), "{err}");
    for (bad, want) in [
        ("v 0 0\n", "line 1: a vertex needs three coordinates"),
        ("v 0 0 nan\n", "line 1: coordinate 3 is not a finite"),
        ("v 0 0 0\nf 1 1\n", "line 2: a face needs at least three"),
        ("v 0 0 0\nf 1 a 1\n", "line 2: 'a' is not a vertex number"),
        ("v 0 0 0\n\nf 1 1 2\n", "line 3: vertex 2 does not exist"),
        ("v 0 0 0\nf 1 1 -2\n", "line 2: vertex -2 does not exist"),
    ] {
        let err = parse(bad.as_bytes()).unwrap_err().to_string();
        assert!(err.starts_with(want), "{bad:?}: {err}");
    }
}
