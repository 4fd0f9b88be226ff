//! `rgc stiffening`: the elastic moduli one rod below and at each
//! sequence's critical number of a truth study, resumable, one line per
//! sequence.

use crate::cli::{fails, rgc};
use rgc::moduli::Solver;
use rgc::threshold::sequence::Record;
use rgc::threshold::stiffening::{self, SequenceStiffening};

/// `rgc stiffening` of the first sequence of box 3.5 of the study `study`
/// at `densities` into `out`, with `more` arguments.
fn box_3_5_run(study: &str, densities: &str, out: &str, more: &[&str]) -> std::process::Output {
    let mut args = vec![
        "stiffening",
        study,
        "--densities",
        densities,
        "--boxes",
        "3.5",
    ];
    args.extend(["--sequences", "1", "--quiet", "--out", out]);
    args.extend_from_slice(more);
    rgc(&args)
}

fn ok(args: &[&str]) -> String {
    let o = rgc(args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// At the rod where the rods first resist every strain of the box (a study
/// of the solid criterion), the strain rank reaches 6 from below, and the
/// shear modulus is zero exactly where the strain rank is. A rerun adds
/// nothing.
#[test]
fn the_moduli_are_measured_across_the_solid_critical_rod_and_resume() {
    let dir = crate::scratch("stiffening");
    let study = dir.join("solid");
    let s = study.to_str().unwrap();
    // The analysis of so few sequences may fail; the records are written.
    let _ = rgc(&[
        "threshold",
        "--kind",
        "truth",
        "--criterion",
        "solid",
        "--gamma",
        "23",
        "--boxes",
        "3,3.5,4",
        "--sequences",
        "5",
        "--seed",
        "1",
        "--quiet",
        "--out",
        s,
    ]);
    let out = dir.join("moduli");
    let o = out.to_str().unwrap();
    let summary = dir.join("summary");
    let args = [
        "stiffening",
        s,
        "--densities",
        "30,40",
        "--boxes",
        "3",
        "--sequences",
        "2",
        "--quiet",
        "--out",
        o,
        "--marks",
        "results/g23-truth",
        "--summary",
        summary.to_str().unwrap(),
    ];
    let printed = ok(&args);
    assert!(printed.contains("    23     3    2 "), "{printed}");
    let lines = out.join("stiffening.jsonl");
    let all = stiffening::read(&lines).unwrap();
    assert_eq!(all.len(), 2);
    // Every sequence is a line: the sides saved in progress are gone.
    assert!(!out.join("partial").exists());
    let records: Vec<Record> = std::fs::read_to_string(study.join("records.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .filter(|r: &Record| r.box_len == 3.0)
        .collect();
    for SequenceStiffening {
        index,
        before,
        at,
        grid,
        ..
    } in &all
    {
        // The grid's prefixes: density times the box's volume, 27.
        assert_eq!(grid.iter().map(|g| g.rods).collect::<Vec<_>>(), [810, 1080]);
        let r = records.iter().find(|r| r.index == *index).unwrap();
        assert_eq!(Some(at.rods), r.rigid_critical);
        assert_eq!(before.rods + 1, at.rods);
        assert_eq!(at.strain_rank, Some(6));
        assert!(before.strain_rank < Some(6), "{before:?}");
        for side in [before, at].into_iter().chain(grid) {
            assert_eq!(side.failed, None);
            let g = side.shear.unwrap();
            assert_eq!(g == 0.0, side.strain_rank == Some(0), "{side:?}");
            // No floats where the exact rank says the tensor is zero.
            if g == 0.0 {
                assert_eq!((side.realization.as_deref(), side.born_shear), (None, None));
            } else {
                assert!(g < side.born_shear.unwrap(), "{side:?}");
            }
            assert!(side.largest.unwrap() <= side.rods);
        }
    }
    let text = std::fs::read_to_string(&lines).unwrap();
    ok(&args[..args.len() - 4]);
    assert_eq!(std::fs::read_to_string(&lines).unwrap(), text);
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let b = &doc["boxes"][0];
    assert_eq!(
        (b["sequences"].as_u64(), b["measured"].as_u64()),
        (Some(2), Some(2))
    );
    assert_eq!(b["solid_at"], 2);
    assert_eq!(b["strain_rank_at"]["mean"], 6.0);
    for chart in ["summary.svg", "summary.png"] {
        assert!(dir.join(chart).metadata().unwrap().len() > 1000, "{chart}");
    }
    let densities: Vec<f64> = b["grid"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["density"].as_f64().unwrap())
        .collect();
    assert_eq!(densities, [30.0, 40.0]);
    // Far above the threshold both sequences are solids, and G averages theirs.
    let top = &b["grid"][1];
    assert_eq!(
        (top["measured"].as_u64(), top["solid"].as_u64()),
        (Some(2), Some(2))
    );
    let g: Vec<f64> = all.iter().map(|s| s.grid[1].shear.unwrap()).collect();
    assert!((top["shear"]["mean"].as_f64().unwrap() - (g[0] + g[1]) / 2.0).abs() < 1e-15);
    // Another box joins the summary: the shear modulus at the critical rod
    // by box.
    let box_3_5_into = |densities: &str, into: &std::path::Path, more: &[&str]| {
        box_3_5_run(s, densities, into.to_str().unwrap(), more)
    };
    let box_3_5 = |densities: &str, into: &std::path::Path| {
        let out = box_3_5_into(densities, into, &["--with", o]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let other = dir.join("moduli-3.5");
    let printed = box_3_5("30,40", &other);
    let g_at = |seqs: &[SequenceStiffening]| {
        seqs.iter().map(|s| s.at.shear.unwrap()).sum::<f64>() / seqs.len() as f64
    };
    let geometric = |seqs: &[SequenceStiffening]| {
        let logs = seqs.iter().map(|s| s.at.shear.unwrap().ln()).sum::<f64>();
        (logs / seqs.len() as f64).exp()
    };
    let joined = stiffening::read(&other.join("stiffening.jsonl")).unwrap();
    let by_box = format!(
        "gamma 23: G at the critical rod by box L = 3: mean {:.3e}, geometric {:.3e} (2), \
         L = 3.5: mean {:.3e}, geometric {:.3e} (1)",
        g_at(&all),
        geometric(&all),
        g_at(&joined),
        geometric(&joined)
    );
    assert!(printed.contains(&by_box), "{printed}");
    // A box may stop its grid lower (a larger box costs more per side):
    // each box keeps its own points.
    let printed = box_3_5("30", &dir.join("moduli-3.5-lower"));
    for (line, there) in [
        ("gamma 23 box 3 rho 40:", true),
        ("gamma 23 box 3.5 rho 30:", true),
        ("gamma 23 box 3.5 rho 40:", false),
    ] {
        assert_eq!(printed.contains(line), there, "{line}: {printed}");
    }
    // The lower grid extended to the other's: only the new side is
    // measured (here by LSMR), the old sides stay as they were, and the
    // new one is the other directory's side (by the QR).
    let lower = dir.join("moduli-3.5-lower");
    let before = stiffening::read(&lower.join("stiffening.jsonl")).unwrap();
    let extend = |densities: &str, solver: &str| {
        box_3_5_into(densities, &lower, &["--extend", "--solver", solver])
    };
    assert!(extend("30,40", "lsmr").status.success());
    let after = stiffening::read(&lower.join("stiffening.jsonl")).unwrap();
    assert_eq!((after.len(), after[0].grid.len()), (1, 2));
    assert_eq!(
        (&after[0].before, &after[0].at, &after[0].grid[0]),
        (&before[0].before, &before[0].at, &before[0].grid[0])
    );
    let (new, qr) = (&after[0].grid[1], &joined[0].grid[1]);
    assert_eq!(
        (new.solver, qr.solver),
        (Some(Solver::Lsmr), Some(Solver::Qr))
    );
    let (a, b) = (new.shear.unwrap(), qr.shear.unwrap());
    assert!((a / b - 1.0).abs() < 1e-8, "{a} by LSMR, {b} by the QR");
    assert!(after[0].seconds > before[0].seconds);
    // Again: nothing to add. A grid that does not continue the old one,
    // and a solver left to the memory free, are refused.
    let text = std::fs::read_to_string(lower.join("stiffening.jsonl")).unwrap();
    assert!(extend("30,40", "lsmr").status.success());
    assert_eq!(
        std::fs::read_to_string(lower.join("stiffening.jsonl")).unwrap(),
        text
    );
    let refused = |densities: &str, solver: &str, needle: &str| {
        let o = extend(densities, solver);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains(needle), "{err}");
    };
    refused("30,36", "qr", "--extend adds densities after the last of");
    refused("30,40,45", "auto", "solves by the QR or by LSMR");
    // LSMR cut short leaves sides unsettled (upper bounds); --extend with
    // a larger cap measures again only those, and they come out as the
    // QR's, while a smaller cap is refused.
    let short = dir.join("moduli-3.5-short");
    let run_short = |more: &[&str]| {
        let args = [&["--solver", "lsmr"], more].concat();
        let o = box_3_5_into("30,40", &short, &args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        stiffening::read(&short.join("stiffening.jsonl")).unwrap()
    };
    let cut = run_short(&["--lsmr-iterations", "3"]);
    let sides = |s: &SequenceStiffening| {
        [
            s.before.clone(),
            s.at.clone(),
            s.grid[0].clone(),
            s.grid[1].clone(),
        ]
    };
    let unsettled: Vec<bool> = sides(&cut[0]).iter().map(|s| s.unsettled()).collect();
    assert_eq!(unsettled, [true, true, false, true], "{cut:?}");
    assert_eq!(cut[0].at.lsmr_iterations, Some(3));
    let settled = run_short(&["--extend"]);
    for (was, now) in sides(&cut[0]).iter().zip(&sides(&settled[0])) {
        if was.unsettled() {
            assert_eq!(
                (now.settled, now.lsmr_iterations),
                (Some(true), Some(rgc::moduli::LSMR_ITERATIONS))
            );
            assert!(now.shear.unwrap() < was.shear.unwrap(), "{was:?} {now:?}");
        } else {
            assert_eq!(was, now);
        }
    }
    let (a, b) = (settled[0].grid[1].shear.unwrap(), qr.shear.unwrap());
    assert!((a / b - 1.0).abs() < 1e-8, "{a} by LSMR, {b} by the QR");
    assert!(settled[0].seconds > cut[0].seconds);
    let smaller = box_3_5_into(
        "30,40",
        &short,
        &["--extend", "--solver", "lsmr", "--lsmr-iterations", "3"],
    );
    let err = String::from_utf8_lossy(&smaller.stderr);
    assert_eq!(smaller.status.code(), Some(2), "{err}");
    assert!(
        err.contains(&format!(
            "or raises LSMR's iterations per strain ({})",
            rgc::moduli::LSMR_ITERATIONS
        )),
        "{err}"
    );
    // One box on two grids is refused before any work.
    let two = dir.join("two-grids");
    fails(
        &[
            "stiffening",
            s,
            "--densities",
            "30",
            "--boxes",
            "3",
            "--sequences",
            "1",
            "--out",
            two.to_str().unwrap(),
            "--with",
            o,
        ],
        "box 3 at gamma 23 was measured at densities [30.0] and at [30.0, 40.0]: join a box's measurements only on one grid",
    );
    assert!(!two.exists());
    fails(
        &[
            "stiffening",
            s,
            "--k",
            "2",
            "--out",
            two.to_str().unwrap(),
            "--with",
            o,
        ],
        "measured with k = 1, this measurement with k = 2: join only measurements of one spring stiffness",
    );
    // The measurement itself again: its sequences repeat.
    let again = [&args[..11], &["--with", o]].concat();
    fails(
        &again,
        &format!(
            "measured sequence {} of box 3 at gamma 23 again: join measurements of other boxes",
            all[0].index
        ),
    );
    fails(
        &["stiffening", s, "--densities", "38,30", "--out", o],
        "--densities must increase and be positive, not [38.0, 30.0]",
    );
    fails(
        &["stiffening", s, "--k", "0", "--out", o],
        "the spring stiffness k must be positive and finite, not 0",
    );
    let _ = std::fs::remove_dir_all(&dir);
}
