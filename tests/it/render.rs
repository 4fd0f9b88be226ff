//! `rgc render` and its library picture: rods at known places land on known
//! pixels in the highlight colour and nowhere else, as wide as the rod; a
//! near rod covers a far one whatever their groups; the legend counts the
//! rods; walls and periodic faces are drawn differently; rods from a file
//! are titled by the file; `--truth` highlights truth's cluster.

use nalgebra::Vector3;
use serde_json::Value;

use crate::cli::{rgc, stdout_of};
use rgc::plot::rods::{Groups, HIGHLIGHT, SIZE, View, pixel_of, rods_pixels};
use rgc::rods::{Domain, Periodic, Rod, RodSystem};

/// Looking along +y: x to the right, z up, y away from the viewer.
const FRONT: View = View {
    azimuth: 0.0,
    elevation: 0.0,
};

const FREE: [u8; 3] = [211, 211, 211];
const RED: [u8; 3] = [HIGHLIGHT.0, HIGHLIGHT.1, HIGHLIGHT.2];

/// Rods (centre, axis, length) of radius `radius` in a box of side 4 with walls.
fn system(rods: &[([f64; 3], [f64; 3], f64)], radius: f64) -> RodSystem {
    RodSystem {
        domain: Domain {
            sides: [4.0; 3],
            periodic: Periodic::None,
        },
        rods: rods
            .iter()
            .map(|&(c, a, l)| Rod::new(Vector3::from(c), Vector3::from(a), l, radius))
            .collect(),
    }
}

fn groups<'a>(groups: Vec<(&'a [u32], bool)>) -> Groups<'a> {
    Groups {
        noun: "body",
        nouns: "bodies",
        groups,
    }
}

/// The colour at pixel (column, row).
fn at(px: &[u8], (x, y): (i32, i32)) -> [u8; 3] {
    let i = 3 * (y as usize * SIZE.0 as usize + x as usize);
    [px[i], px[i + 1], px[i + 2]]
}

#[test]
fn the_highlighted_rod_is_red_where_it_lies_as_wide_as_it_is_and_nowhere_else() {
    let x = [1.0, 0.0, 0.0];
    let z = [0.0, 0.0, 1.0];
    // Rod 0 spans its body (the highlight), rod 1 is another body, rod 2 free.
    let s = system(
        &[
            ([2.0, 2.0, 1.0], x, 2.0),
            ([3.5, 2.0, 3.0], z, 1.0),
            ([1.0, 2.0, 3.0], z, 1.0),
        ],
        0.02,
    );
    let g = groups(vec![(&[0][..], true), (&[1][..], false)]);
    let px = rods_pixels(&s, &g, FRONT).unwrap();
    let pixel = |p: [f64; 3]| pixel_of(&s, &g, FRONT, Vector3::from(p));
    // The box from 0 to 4 fills the picture: one rod length is `scale` pixels.
    let scale = f64::from(pixel([1.0, 0.0, 0.0]).0 - pixel([0.0, 0.0, 0.0]).0);
    assert!(scale > 200.0, "{scale}");
    for k in 1..20 {
        let on = pixel([1.0 + 0.1 * k as f64, 2.0, 1.0]);
        assert_eq!(at(&px, on), RED, "rod 0 at {on:?}");
    }
    // Red only on rod 0's stroke: within half its width of the core's line.
    let width = 2.0 * 0.02 * scale;
    let (left, right, row) = (
        pixel([1.0, 2.0, 1.0]).0,
        pixel([3.0, 2.0, 1.0]).0,
        pixel([2.0, 2.0, 1.0]).1,
    );
    let mut red_rows = Vec::new();
    for (i, p) in px.chunks(3).enumerate() {
        if p == RED {
            let (c, r) = ((i % SIZE.0 as usize) as i32, (i / SIZE.0 as usize) as i32);
            assert!(
                (left - 1..=right + 1).contains(&c)
                    && f64::from((r - row).abs()) <= width / 2.0 + 1.0,
                "red at {c},{r}, off rod 0"
            );
            if c == pixel([2.0, 2.0, 1.0]).0 {
                red_rows.push(r);
            }
        }
    }
    // As wide as the rod: the column through its middle is red for its diameter.
    assert!(
        (red_rows.len() as f64 - width).abs() <= 1.0,
        "{} red pixels across a rod {width:.1} pixels wide",
        red_rows.len()
    );
    let other = at(&px, pixel([3.5, 2.0, 3.0]));
    assert!(
        other != RED && other != FREE && other != [255; 3],
        "{other:?}"
    );
    assert_eq!(at(&px, pixel([1.0, 2.0, 3.0])), FREE);
    // Without bodies nothing is red: the colour means the chosen group.
    let px = rods_pixels(&s, &groups(vec![]), FRONT).unwrap();
    assert_eq!(px.chunks(3).filter(|p| *p == RED).count(), 0);
    // A thin rod is still a pixel wide.
    let thin = system(&[([2.0, 2.0, 1.0], x, 2.0)], 1e-5);
    let g = groups(vec![(&[0][..], true)]);
    let px = rods_pixels(&thin, &g, FRONT).unwrap();
    assert_eq!(
        at(&px, pixel_of(&thin, &g, FRONT, Vector3::new(2.0, 2.0, 1.0))),
        RED
    );
    // A view that cannot be is refused.
    let bad = View {
        azimuth: 0.0,
        elevation: 120.0,
    };
    let err = rods_pixels(&s, &g, bad).unwrap_err().to_string();
    assert!(err.contains("elevation within -90..90"), "{err}");
}

/// Two rods crossing on screen: whichever is nearer covers the other where
/// they cross, whatever their order in the system and whichever is
/// highlighted.
#[test]
fn a_near_rod_covers_a_far_one_where_they_cross() {
    let (x, z) = ([1.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
    for (red_y, free_y, want) in [(3.0, 1.0, FREE), (1.0, 3.0, RED)] {
        for red_first in [true, false] {
            let red = ([2.0, red_y, 2.0], z, 2.0);
            let free = ([2.0, free_y, 2.0], x, 2.0);
            let (rods, red_index) = if red_first {
                ([red, free], 0u32)
            } else {
                ([free, red], 1u32)
            };
            let s = system(&rods, 0.02);
            let index = [red_index];
            let g = groups(vec![(&index[..], true)]);
            let px = rods_pixels(&s, &g, FRONT).unwrap();
            let pixel = |p: [f64; 3]| pixel_of(&s, &g, FRONT, Vector3::from(p));
            assert_eq!(
                at(&px, pixel([2.0, 2.0, 2.0])),
                want,
                "highlight at y = {red_y}, free rod at y = {free_y}"
            );
            // Away from the crossing each rod shows its own colour.
            assert_eq!(at(&px, pixel([2.0, red_y, 2.8])), RED);
            assert_eq!(at(&px, pixel([2.8, free_y, 2.0])), FREE);
        }
    }
}

/// Strokes of one colour in an SVG: their widths.
fn strokes(svg: &str, colour: &str) -> Vec<u32> {
    svg.split("<polyline ")
        .skip(1)
        .filter(|p| p.contains(&format!("stroke=\"{colour}\"")))
        .map(|p| {
            p.split("stroke-width=\"")
                .nth(1)
                .unwrap()
                .split('"')
                .next()
                .unwrap()
                .parse()
                .unwrap()
        })
        .collect()
}

/// `render --rods FILE` of three free rods in each kind of box: the title
/// names the file and its rods (no seed, no density), the legend counts the
/// rods, each rod is one stroke as wide as it is (a thin one a pixel), wall
/// edges solid and thick, periodic ones dashed and thin.
#[test]
fn render_of_a_rods_file_titles_it_and_draws_walls_apart_from_periodic_faces() {
    let dir = crate::scratch("render-file");
    let csv = dir.join("three.csv");
    std::fs::write(
        &csv,
        "x,y,z,dx,dy,dz,length,radius\n1,1,1,1,0,0,1,0.05\n3,3,3,0,1,0,1,0.05\n2,2,2,0,0,1,1,0.001\n",
    )
    .unwrap();
    // (periodic, wall edges, dashed edges, legend's box line)
    let boxes = [
        ("xy", 8, true, "box: walls solid, periodic faces dashed"),
        ("none", 12, false, "box: walls (solid edges)"),
        ("xyz", 0, true, "box: periodic faces (dashed edges)"),
    ];
    for (periodic, walls, dashed, line) in boxes {
        let prefix = dir.join(periodic);
        stdout_of(&[
            "render",
            "--rods",
            csv.to_str().unwrap(),
            "--box",
            "4",
            "--periodic",
            periodic,
            "--out",
            prefix.to_str().unwrap(),
        ]);
        let svg = std::fs::read_to_string(prefix.with_extension("svg")).unwrap();
        assert!(
            svg.contains("three.csv: 3 rods, box 4, rules sound"),
            "title"
        );
        assert!(!svg.contains("seed") && !svg.contains("density"));
        assert!(svg.contains("rods in no body: 3"));
        assert!(!svg.contains("spanning") && !svg.contains("other bodies"));
        assert!(svg.contains(line), "{periodic}: {line}");
        assert_eq!(
            strokes(&svg, "#282828"),
            vec![3; walls],
            "{periodic}: wall edges"
        );
        let dashes = strokes(&svg, "#6E6E6E");
        assert_eq!(!dashes.is_empty(), dashed, "{periodic}: dashed edges");
        assert!(dashes.iter().all(|&w| w == 1));
        let mut rods = strokes(&svg, "#D3D3D3");
        rods.sort_unstable();
        assert_eq!(rods.len(), 3, "one stroke per rod");
        assert_eq!(rods[0], 1, "the thin rod is a pixel wide");
        assert!(rods[1] == rods[2] && rods[1] > 10, "{rods:?}");
        let png = std::fs::read(prefix.with_extension("png")).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        // IHDR: width and height, big-endian, after the chunk length and type.
        let dim = |at: usize| u32::from_be_bytes(png[at..at + 4].try_into().unwrap());
        assert_eq!((dim(16), dim(20)), SIZE);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The number after `label` in the SVG's text, e.g. `1,234` as 1234.
fn count_after(svg: &str, label: &str) -> Option<usize> {
    let at = svg.find(label)? + label.len();
    let digits: String = svg[at..]
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == ',')
        .filter(char::is_ascii_digit)
        .collect();
    digits.parse().ok()
}

/// Regression (`render --truth` was once a silent no-op): with `--truth` the
/// legend names truth's cluster with the rods `rgc truth` finds in it on the
/// same system, and the rods in no cluster; without, the reported run's body,
/// which holds fewer rods here.
#[test]
fn render_truth_highlights_truths_cluster() {
    let dir = crate::scratch("render-truth");
    let system = [
        "--gamma",
        "23",
        "--box",
        "4",
        "--density",
        "40",
        "--seed",
        "2",
    ];
    let render = |extra: &[&str], name: &str| {
        let prefix = dir.join(name);
        let args = [
            &["render"][..],
            &system,
            extra,
            &["--out", prefix.to_str().unwrap()],
        ]
        .concat();
        stdout_of(&args);
        std::fs::read_to_string(prefix.with_extension("svg")).unwrap()
    };
    let (with, without) = (render(&["--truth"], "truth"), render(&[], "bodies"));
    let out = rgc(&[&["truth"][..], &system, &["--json"]].concat());
    assert!(out.status.success());
    let t: Value = serde_json::from_slice(&out.stdout).unwrap();
    let clusters = t["clusters"].as_array().unwrap();
    let size = |c: &Value| c["rods"].as_array().unwrap().len();
    let spanning = clusters.iter().find(|c| c["spans"]["wrap"] == true);
    let (label, want) = match spanning {
        Some(c) => ("spanning true rigid cluster: ", size(c)),
        None => (
            "largest true rigid cluster (none spans): ",
            size(&clusters[0]),
        ),
    };
    assert_eq!(count_after(&with, label), Some(want), "{label}");
    let mut held: Vec<u64> = clusters
        .iter()
        .flat_map(|c| {
            c["rods"]
                .as_array()
                .unwrap()
                .iter()
                .map(|r| r.as_u64().unwrap())
        })
        .collect();
    held.sort_unstable();
    held.dedup();
    let n = t["n_rods"].as_u64().unwrap() as usize;
    assert_eq!(
        count_after(&with, "rods in no true rigid cluster: "),
        Some(n - held.len())
    );
    assert!(with.contains("exact truth") && !with.contains(" body"));
    let body = count_after(&without, "spanning body: ")
        .or_else(|| count_after(&without, "largest body (none spans): "))
        .expect("the default legend names the body");
    assert!(
        body < want,
        "truth holds more rods rigid: {body} against {want}"
    );
    assert!(!without.contains("true rigid cluster"));
    std::fs::remove_dir_all(&dir).unwrap();
}
