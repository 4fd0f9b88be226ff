//! The defects of issue 31 (section 3), found by a battery of bad inputs
//! run as a new user would: each test fails without its fix. Every test
//! works in its own scratch folder, and runs `rgc` there, so that outputs
//! can be spelt relative to it.

use std::path::Path;
use std::process::{Command, Output};

const REPO: &str = env!("CARGO_MANIFEST_DIR");

/// Runs `rgc` with `args` in `dir`.
fn rgc_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rgc"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn repo(path: &str) -> String {
    Path::new(REPO).join(path).display().to_string()
}

/// Runs a command in `dir` that must be refused: exit code 2, nothing on
/// stdout, and one error line on stderr holding `needle`, no panic and no
/// allocation failure (a usage error adds clap's one line on where to read
/// more).
fn refused_in(dir: &Path, args: &[&str], needle: &str) {
    let out = rgc_in(dir, args);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert!(err.contains(needle), "{args:?}: {err:?} lacks {needle:?}");
    let lines: Vec<&str> = err.lines().collect();
    assert!(lines[0].starts_with("rgc: error: "), "{args:?}: {err}");
    let usage = lines.len() == 2 && lines[1].starts_with("see 'rgc");
    assert!(lines.len() == 1 || usage, "{args:?}: one line: {err}");
    for bad in ["panicked", "memory allocation", "RUST_BACKTRACE"] {
        assert!(!err.contains(bad), "{args:?}: {err}");
    }
    assert!(out.stdout.is_empty(), "{args:?}: {}", text(&out.stdout));
}

fn succeeds_in(dir: &Path, args: &[&str]) -> String {
    let out = rgc_in(dir, args);
    assert!(out.status.success(), "{args:?}: {}", text(&out.stderr));
    text(&out.stdout)
}

/// A small, fast generated system.
const SMALL: [&str; 7] = ["sample", "--gamma", "10", "--box", "3", "--density", "2"];

fn with<'a>(base: &[&'a str], more: &[&'a str]) -> Vec<&'a str> {
    base.iter().chain(more).copied().collect()
}

/// The files in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

// Item 1: two output flags naming one file wrote both into it (exit 0).

#[cfg(unix)]
#[test]
fn two_outputs_naming_one_file_are_refused_however_spelt() {
    let dir = crate::scratch("battery-same-file");
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    let sub = dir.join("sub");
    let both = "--save-rods and --save-contacts both write";
    // Spelt with ./, through ../ from a folder, by an absolute path.
    let absolute = dir.join("alias.csv");
    for (dir, other) in [
        (&dir, "./alias.csv"),
        (&sub, "../alias.csv"),
        (&dir, absolute.to_str().unwrap()),
    ] {
        let rods = if dir == &sub {
            "../alias.csv"
        } else {
            "alias.csv"
        };
        let args = with(&SMALL, &["--save-rods", rods, "--save-contacts", other]);
        refused_in(dir, &args, both);
    }
    assert!(!dir.join("alias.csv").exists(), "nothing was written");
    // A symbolic link to a file not yet made, and a hard link to one made.
    std::os::unix::fs::symlink("alias.csv", dir.join("link.csv")).unwrap();
    refused_in(
        &dir,
        &with(
            &SMALL,
            &["--save-rods", "alias.csv", "--save-contacts", "link.csv"],
        ),
        both,
    );
    std::fs::write(dir.join("alias.csv"), "kept\n").unwrap();
    std::fs::hard_link(dir.join("alias.csv"), sub.join("hard.txt")).unwrap();
    refused_in(
        &dir,
        &with(
            &SMALL,
            &["--save-rods", "alias.csv", "--save-bodies", "sub/hard.txt"],
        ),
        "--save-rods and --save-bodies both write alias.csv and sub/hard.txt, one file",
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("alias.csv")).unwrap(),
        "kept\n"
    );
    // truth's two outputs share the check: --save-clusters onto the VTK file.
    std::os::unix::fs::symlink("c.vtp", dir.join("clusters.json")).unwrap();
    refused_in(
        &dir,
        &[
            "truth",
            "--gamma",
            "10",
            "--box",
            "3",
            "--density",
            "2",
            "--save-vtk",
            "c.vtp",
            "--save-clusters",
            "clusters.json",
        ],
        "--save-vtk and --save-clusters both write c.vtp and clusters.json, one file",
    );
    // Distinct files are written, each its own.
    succeeds_in(
        &dir,
        &with(
            &SMALL,
            &[
                "--save-rods",
                "sub/rods.csv",
                "--save-contacts",
                "./contacts.txt",
            ],
        ),
    );
    let rods = std::fs::read_to_string(sub.join("rods.csv")).unwrap();
    assert!(rods.starts_with("x,y,z,dx,dy,dz,length,radius\n"), "{rods}");
    assert!(
        !std::fs::read_to_string(dir.join("contacts.txt"))
            .unwrap()
            .starts_with("x,")
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

// Item 2: an output that is a symbolic link became a plain file.

#[cfg(unix)]
#[test]
fn an_output_through_a_symbolic_link_keeps_the_link() {
    let dir = crate::scratch("battery-symlink");
    std::fs::create_dir_all(dir.join("data")).unwrap();
    std::fs::write(dir.join("data/rods.csv"), "old\n").unwrap();
    std::os::unix::fs::symlink("data/rods.csv", dir.join("rods.csv")).unwrap();
    succeeds_in(&dir, &with(&SMALL, &["--save-rods", "rods.csv"]));
    let link = std::fs::symlink_metadata(dir.join("rods.csv")).unwrap();
    assert!(link.is_symlink(), "the link stays a link");
    let written = std::fs::read_to_string(dir.join("data/rods.csv")).unwrap();
    assert!(written.starts_with("x,y,z,"), "{written}");
    assert_eq!(names(&dir.join("data")), ["rods.csv"], "no temporary left");
    // What was written through the link reads back as the same system.
    let again = succeeds_in(
        &dir,
        &["sample", "--rods", "rods.csv", "--box", "3", "--json"],
    );
    let first = succeeds_in(&dir, &with(&SMALL, &["--json"]));
    let n = |t: &str| serde_json::from_str::<serde_json::Value>(t).unwrap()["n_contacts"].clone();
    assert_eq!(n(&again), n(&first));
    std::fs::remove_dir_all(&dir).unwrap();
}

// Item 3: a CSV cut inside its last number was read, the number cut short.

#[test]
fn a_rods_file_cut_inside_its_last_number_is_refused_with_the_line() {
    let dir = crate::scratch("battery-cut");
    let whole = "x,y,z,dx,dy,dz,length,radius\n1,1,1,1,0,0,1,0.02\n2,2,2,0,0,1,1,0.025\n";
    std::fs::write(dir.join("whole.csv"), whole).unwrap();
    std::fs::write(dir.join("cut.csv"), &whole[..whole.len() - 2]).unwrap();
    succeeds_in(&dir, &["sample", "--rods", "whole.csv", "--box", "4"]);
    refused_in(
        &dir,
        &["sample", "--rods", "cut.csv", "--box", "4"],
        "malformed rods CSV file cut.csv: line 3: the file ends mid-line",
    );
    let dump = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp pp\n0 4\n0 4\n0 4\n\
                ITEM: ATOMS id x y z mux muy muz length radius\n1 1 1 1 1 0 0 1 0.025\n";
    std::fs::write(dir.join("cut.dump"), &dump[..dump.len() - 2]).unwrap();
    refused_in(
        &dir,
        &["sample", "--rods", "cut.dump"],
        "malformed LAMMPS dump file cut.dump: line 10: the file ends mid-line",
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

// Item 4: `--box 4 --box 5 --box 6` was the box 4,5,6.

#[test]
fn a_repeated_box_or_origin_is_refused_as_a_repeated_seed_is() {
    let dir = crate::scratch("battery-repeat");
    let cases: [(&[&str], &str); 5] = [
        (
            &[
                "sample",
                "--gamma",
                "10",
                "--density",
                "1",
                "--box",
                "4",
                "--box",
                "5",
                "--box",
                "6",
            ],
            "the argument '--box <L|LX,LY,LZ>' cannot be used multiple times",
        ),
        (
            &[
                "sample", "--rods", "r.csv", "--box", "4", "--origin", "0", "--origin", "1,1",
            ],
            "the argument '--origin <O|X,Y,Z>' cannot be used multiple times",
        ),
        (
            &[
                "sample",
                "--gamma",
                "10",
                "--box",
                "4",
                "--density",
                "1",
                "--seed",
                "1",
                "--seed",
                "2",
            ],
            "the argument '--seed <SEED>' cannot be used multiple times",
        ),
        (
            &["threshold", "--boxes", "4", "--boxes", "5,6", "--out", "x"],
            "the argument '--boxes <BOXES>' cannot be used multiple times",
        ),
        (
            &[
                "sample",
                "--gamma",
                "10",
                "--box",
                "4",
                "--density",
                "1",
                "--order",
                "0.5",
                "--director",
                "0,0,1",
                "--director",
                "1,0,0",
            ],
            "the argument '--director <X,Y,Z>' cannot be used multiple times",
        ),
    ];
    for (args, needle) in cases {
        refused_in(&dir, args, needle);
    }
    // One flag with its list still works.
    let v: serde_json::Value = serde_json::from_str(&succeeds_in(
        &dir,
        &[
            "sample",
            "--gamma",
            "10",
            "--density",
            "1",
            "--box",
            "4,5,6",
            "--json",
        ],
    ))
    .unwrap();
    assert_eq!(v["box"], serde_json::json!([4.0, 5.0, 6.0]));
    std::fs::remove_dir_all(&dir).unwrap();
}

// Item 5: a rod wider than long came in through --radius and files, while
// --gamma 0.9 was refused.

#[test]
fn a_rod_wider_than_long_is_refused_however_it_arrives() {
    let dir = crate::scratch("battery-wide");
    refused_in(
        &dir,
        &["sample", "--box", "15", "--density", "0.1", "--radius", "2"],
        "rods of the mean size: radius 2 is more than half the length 1: the rod is wider than long \
         (aspect ratio l / (2r) = 0.2500, at least 1 is needed)",
    );
    refused_in(
        &dir,
        &["sample", "--box", "5", "--density", "1", "--gamma", "0.9"],
        "gamma must be at least 1 (a rod at least as long as it is wide), got 0.9",
    );
    // Each drawn rod, where only some of a distribution are too wide.
    refused_in(
        &dir,
        &[
            "sample",
            "--box",
            "8",
            "--density",
            "2",
            "--length",
            "uniform:0.2,1.8",
            "--radius",
            "0.45",
        ],
        "was drawn too wide: radius 0.45 is more than half the length",
    );
    // As wide as long is the limit, and allowed, as --gamma 1 is.
    succeeds_in(
        &dir,
        &["sample", "--box", "5", "--density", "1", "--radius", "0.5"],
    );
    let header = "x,y,z,dx,dy,dz,length,radius\n";
    std::fs::write(
        dir.join("wide.csv"),
        format!("{header}1,1,1,1,0,0,1,0.02\n2,2,2,0,0,1,1,0.6\n"),
    )
    .unwrap();
    refused_in(
        &dir,
        &["sample", "--rods", "wide.csv", "--box", "5"],
        "malformed rods CSV file wide.csv: line 3: radius 0.6 is more than half the length 1",
    );
    std::fs::write(
        dir.join("wide.json"),
        "{\"box\": [5, 5, 5], \"rods\": [\n{\"center\": [1, 1, 1], \"direction\": [1, 0, 0], \"length\": 0.1, \"radius\": 0.2}\n]}\n",
    )
    .unwrap();
    refused_in(
        &dir,
        &["truth", "--rods", "wide.json"],
        "malformed rods JSON file wide.json: line 2: radius 0.2 is more than half the length 0.1",
    );
    std::fs::write(
        dir.join("wide.dump"),
        "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp pp\n0 5\n0 5\n0 5\n\
         ITEM: ATOMS id x y z mux muy muz\n1 1 1 1 1 0 0\n",
    )
    .unwrap();
    refused_in(
        &dir,
        &[
            "sample",
            "--rods",
            "wide.dump",
            "--lammps-columns",
            "length=1,radius=0.7",
        ],
        "line 10: radius 0.7 is more than half the length 1",
    );
    // The tiny rod whose memory estimate overflowed to "16384 PiB".
    refused_in(
        &dir,
        &[
            "sample",
            "--box",
            "5",
            "--density",
            "1",
            "--length",
            "5e-324",
            "--radius",
            "1e-3",
        ],
        "radius 0.001 is more than half the length 4.9407e-324",
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The library's checked constructor, which Python's `Rods.from_arrays`
/// ends in, refuses a wide rod but keeps a core a wall has cut short.
#[test]
fn the_checked_system_refuses_wide_rods_but_not_cores_cut_at_walls() {
    use nalgebra::Vector3;
    use rgc::rods::{Cut, Domain, Periodic, Rod, RodSystem};
    let domain = Domain::new([4.0, 4.0, 4.0], Periodic::Xy).unwrap();
    let wide = Rod::new(Vector3::new(2.0, 2.0, 2.0), Vector3::x(), 0.1, 0.2);
    let err = RodSystem::new(domain, vec![wide]).unwrap_err().to_string();
    assert_eq!(
        err,
        "invalid parameter: rod 0: radius 0.2 is more than half the length 0.1: the rod is wider \
         than long (aspect ratio l / (2r) = 0.2500, at least 1 is needed)"
    );
    // A rod mostly beyond the wall at z = 0: 0.01 of its core inside.
    let rod = Rod::new(Vector3::new(2.0, 2.0, -0.49), Vector3::z(), 1.0, 0.02);
    assert!(rod.defect().is_none());
    let Cut::Cut(cut) = domain.cut(&rod) else {
        panic!("the core crosses the wall")
    };
    assert!(cut.length < 2.0 * cut.radius, "{cut:?}");
    assert_eq!(RodSystem::new(domain, vec![cut]).unwrap().len(), 1);
}

// Item 6: the README said a centre outside a periodic side stops the read;
// it is wrapped, which a simulation's unwrapped coordinates need.

#[test]
fn centres_outside_a_periodic_side_are_wrapped_and_counted() {
    let dir = crate::scratch("battery-wrap");
    let header = "x,y,z,dx,dy,dz,length,radius\n";
    std::fs::write(
        dir.join("unwrapped.csv"),
        format!("{header}-0.5,1,1,1,0,0,1,0.02\n1,9,1,0,1,0,1,0.02\n2,2,2,0,0,1,1,0.02\n"),
    )
    .unwrap();
    let printed = succeeds_in(&dir, &["sample", "--rods", "unwrapped.csv", "--box", "4"]);
    assert!(
        printed.starts_with("2 rod centres wrapped into the box along periodic axes\n"),
        "{printed}"
    );
    let v: serde_json::Value = serde_json::from_str(&succeeds_in(
        &dir,
        &["sample", "--rods", "unwrapped.csv", "--box", "4", "--json"],
    ))
    .unwrap();
    assert_eq!(
        (v["wrapped"].clone(), v["n_rods"].clone()),
        (2.into(), 3.into())
    );
    // Along a wall a centre is not moved: a core wholly outside stops the read.
    refused_in(
        &dir,
        &[
            "sample",
            "--rods",
            "unwrapped.csv",
            "--box",
            "4",
            "--periodic",
            "none",
        ],
        "line 2: rod at (-0.5, 1, 1) lies wholly outside the walls of the box 4",
    );
    // And the README says so.
    let readme = std::fs::read_to_string(Path::new(REPO).join("README.md")).unwrap();
    let prose: String = readme.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(
        prose.contains("a centre outside a periodic side (a # simulation's unwrapped coordinates, a centred box) is wrapped into it; the # report counts both"),
        "README: the wrapped centres"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

// Item 7: `rgc rules --out existing.json` replaced it without --force.

#[test]
fn rules_refuses_to_replace_a_file_without_force() {
    let dir = crate::scratch("battery-rules");
    std::fs::write(dir.join("mine.json"), "my own\n").unwrap();
    refused_in(
        &dir,
        &["rules", "--out", "mine.json"],
        "mine.json exists; choose another --out, or --force to replace it",
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("mine.json")).unwrap(),
        "my own\n"
    );
    succeeds_in(&dir, &["rules", "--out", "mine.json", "--force"]);
    assert_eq!(
        std::fs::read(dir.join("mine.json")).unwrap(),
        std::fs::read(Path::new(REPO).join("motifs/base.json")).unwrap()
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

// Item 8: paired and transition failed on a missing parent of --out.

#[test]
fn paired_and_transition_make_the_folder_of_their_out_prefix() {
    let dir = crate::scratch("battery-parents");
    succeeds_in(
        &dir,
        &[
            "paired",
            &repo("results/g23-rigid-sound"),
            &repo("results/g23-rigid-sound-extended"),
            "--out",
            "new/deeper/paired",
        ],
    );
    assert_eq!(
        names(&dir.join("new/deeper")),
        [
            "paired.csv",
            "paired.json",
            "paired.md",
            "paired.png",
            "paired.svg"
        ]
    );
    succeeds_in(
        &dir,
        &["transition", &repo("results/g48-truth"), "--out", "other/t"],
    );
    assert_eq!(
        names(&dir.join("other")),
        ["t.csv", "t.histogram.csv", "t.json", "t.png", "t.svg"]
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

// Item 9: messages with 300 digits, a raw os error.

#[test]
fn numbers_and_files_in_messages_are_named_shortly() {
    let dir = crate::scratch("battery-messages");
    refused_in(
        &dir,
        &[
            "sample",
            "--gamma",
            "10",
            "--box",
            "1e-300",
            "--density",
            "1",
        ],
        "box 1.0000e-300 is too small",
    );
    refused_in(
        &dir,
        &[
            "sample",
            "--gamma",
            "10",
            "--box",
            "1e-300,1,1",
            "--density",
            "1e301",
        ],
        "box side 1.0000e-300 along x is too small",
    );
    refused_in(
        &dir,
        &[
            "sample",
            "--gamma",
            "1e-300",
            "--box",
            "4",
            "--density",
            "1",
        ],
        "gamma must be at least 1 (a rod at least as long as it is wide), got 1.0000e-300",
    );
    for (args, needle) in [
        (
            &[
                "sample",
                "--gamma",
                "10",
                "--box",
                "1e-300",
                "--density",
                "1",
            ][..],
            "",
        ),
        (
            &[
                "sample",
                "--box",
                "-1e-300",
                "--radius",
                "0.1",
                "--density",
                "1",
            ][..],
            "box sides must be positive finite numbers, got -1.0000e-300",
        ),
    ] {
        let out = rgc_in(&dir, args);
        let err = text(&out.stderr);
        assert!(err.len() < 300, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    std::fs::write(dir.join("plain"), "").unwrap();
    refused_in(
        &dir,
        &["merge", &repo("results/g23-contact"), "--out", "plain"],
        "--out plain is a file, not a directory",
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A tiny study (5 sequences in boxes 3 to 4) whose resamples put the
/// threshold below 0: its interval read `[-2.0880, 11.9174]` and c0 at the
/// threshold `[-0.1069, 2.5308]`. A fit with a density at or below 0 now
/// fails like any failed resample, and a contact number stops at 0.
#[test]
fn a_tiny_study_has_no_negative_density_in_its_intervals() {
    let dir = crate::scratch("battery-negative");
    let v: serde_json::Value = serde_json::from_str(&succeeds_in(
        &dir,
        &[
            "threshold",
            "--kind",
            "contact",
            "--gamma",
            "10",
            "--boxes",
            "3,3.5,4",
            "--sequences",
            "5",
            "--bootstrap",
            "100",
            "--seed",
            "18",
            "--quiet",
            "--out",
            "st",
            "--json",
        ],
    ))
    .unwrap();
    let fss = &v["summary"]["fss"];
    let lo = |e: &serde_json::Value| e["lo"].as_f64().unwrap();
    assert!(lo(&fss["threshold"]) > 0.0, "{}", fss["threshold"]);
    assert!(lo(&fss["threshold"]) <= fss["threshold"]["value"].as_f64().unwrap());
    // Some resamples failed on it, and say why.
    assert!(fss["bootstrap_failures"].as_u64().unwrap() > 0);
    let warnings = fss["warnings"].to_string();
    assert!(
        warnings.contains("not a positive density") || warnings.contains("nu would be"),
        "{warnings}"
    );
    for b in fss["boxes"].as_array().unwrap() {
        for i in b["rho_x_intervals"].as_array().unwrap() {
            assert!(i[0].as_f64().unwrap() > 0.0, "{b}");
        }
    }
    let c0 = &fss["contact_numbers"]["pooled"]["c0"]["at_threshold"];
    assert!(lo(c0) >= 0.0, "{c0}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The whole battery in one table: bad inputs a new user tries, each
/// refused with exit code 2 and one line naming the problem.
#[test]
fn the_battery_of_bad_inputs_is_refused_in_one_line_each() {
    let dir = crate::scratch("battery-table");
    std::fs::write(dir.join("plain"), "").unwrap();
    std::fs::write(dir.join("empty.csv"), "").unwrap();
    std::fs::write(
        dir.join("cut.csv"),
        "x,y,z,dx,dy,dz,length,radius\n1,1,1,1,0,0,1,0.0",
    )
    .unwrap();
    std::fs::write(
        dir.join("nan.csv"),
        "x,y,z,dx,dy,dz,length,radius\n1,NaN,1,1,0,0,1,0.02\n",
    )
    .unwrap();
    let cases: &[(&[&str], &str)] = &[
        (
            &[
                "sample",
                "--gamma",
                "10",
                "--box",
                "3",
                "--density",
                "2",
                "--save-rods",
                "a.csv",
                "--save-contacts",
                "./a.csv",
            ],
            "both write",
        ),
        (
            &[
                "sample",
                "--gamma",
                "10",
                "--box",
                "4",
                "--box",
                "5",
                "--density",
                "1",
            ],
            "cannot be used multiple times",
        ),
        (
            &["sample", "--box", "4", "--density", "1", "--radius", "3"],
            "wider than long",
        ),
        (
            &["sample", "--box", "4", "--density", "1", "--gamma", "0.5"],
            "gamma must be at least 1",
        ),
        (
            &[
                "sample",
                "--box",
                "4",
                "--density",
                "1",
                "--length",
                "1e-300",
                "--radius",
                "1",
            ],
            "wider than long",
        ),
        (
            &["sample", "--box", "0", "--gamma", "10", "--density", "1"],
            "box must be a positive finite number, got 0",
        ),
        (
            &["sample", "--box", "nan", "--gamma", "10", "--density", "1"],
            "box sides must be positive finite numbers, got NaN",
        ),
        (
            &[
                "sample",
                "--box",
                "4",
                "--gamma",
                "10",
                "--density",
                "1e300",
            ],
            "more than the 50000000 that fit in memory",
        ),
        (
            &["sample", "--box", "4", "--gamma", "10", "--density", "-1"],
            "density must be a positive finite number",
        ),
        (
            &["sample", "--rods", "cut.csv", "--box", "4"],
            "line 2: the file ends mid-line",
        ),
        (
            &["sample", "--rods", "nan.csv", "--box", "4"],
            "line 2: y is NaN, not a finite number",
        ),
        (
            &["sample", "--rods", "empty.csv", "--box", "4"],
            "empty.csv",
        ),
        (
            &["sample", "--rods", "missing.csv", "--box", "4"],
            "missing.csv",
        ),
        (
            &[
                "sample",
                "--gamma",
                "10",
                "--box",
                "4",
                "--density",
                "1",
                "--save-bodies",
                "plain/b.json",
            ],
            "plain",
        ),
        (
            &["rules", "--out", "plain"],
            "plain exists; choose another --out, or --force to replace it",
        ),
        (
            &["merge", "plain", "--out", "plain"],
            "--out plain is a file, not a directory",
        ),
        (
            &["stability", "--out", "plain"],
            "plain: is a file, not a directory",
        ),
        (&["transition", "plain"], "plain"),
        (
            &["paired", "plain", "plain", "--out", "x/"],
            "is a directory: give a file name prefix",
        ),
        (
            &["threshold", "--boxes", "4,5", "--out", "s"],
            "nu needs at least 3 box sizes, got 2",
        ),
        (
            &[
                "threshold",
                "--boxes",
                "4,5,6",
                "--sequences",
                "2",
                "--out",
                "s",
            ],
            "at least",
        ),
        (&["truth", "--graph6", "not graph6!"], "graph6"),
        (&["compress", "--graph6", "~~~~"], "graph6"),
        (&["check", "--graph6", ""], "graph6"),
    ];
    for (args, needle) in cases {
        refused_in(&dir, args, needle);
    }
    // Nothing was made where a refusal came first.
    assert_eq!(names(&dir), ["cut.csv", "empty.csv", "nan.csv", "plain"]);
    std::fs::remove_dir_all(&dir).unwrap();
}
