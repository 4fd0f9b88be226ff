//! Rods read from standard input (`--rods -`): the same answers as from a
//! file, the format told by the text or `--rods-format`, and the errors
//! naming standard input.

use std::io::Write;
use std::process::{Command, Output, Stdio};

use serde_json::Value;

use crate::scratch;

/// `rgc args` with `input` on its standard input.
fn rgc_with_input(args: &[&str], input: &[u8]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_rgc"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    child.stdin.take().unwrap().write_all(input).unwrap();
    child.wait_with_output().unwrap()
}

fn summary(out: &Output) -> Value {
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut v: Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    v.as_object_mut().unwrap().remove("seconds");
    v
}

#[test]
fn rods_from_standard_input_give_the_answers_of_their_file() {
    let dir = scratch("stdin-same-answers");
    for ext in ["csv", "json", "dump"] {
        let file = dir.join(format!("rods.{ext}"));
        let file = file.to_str().unwrap();
        let made = Command::new(env!("CARGO_BIN_EXE_rgc"))
            .args(["sample", "--gamma", "23", "--box", "4", "--density", "30"])
            .args(["--seed", "5", "--save-rods", file])
            .output()
            .unwrap();
        assert!(made.status.success());
        let boxed: &[&str] = if ext == "csv" { &["--box", "4"] } else { &[] };
        let from_file =
            rgc_with_input(&[&["truth", "--rods", file, "--json"], boxed].concat(), b"");
        let text = std::fs::read(file).unwrap();
        let from_stdin = rgc_with_input(
            &[&["truth", "--rods", "-", "--json"], boxed].concat(),
            &text,
        );
        let (a, b) = (summary(&from_file), summary(&from_stdin));
        assert!(a["n_rods"].as_u64().unwrap() > 100, "{ext}: {a}");
        assert_eq!(a, b, "{ext}: standard input differs from the file");
    }
}

#[test]
fn the_format_of_standard_input_can_be_named() {
    // A CSV table told to be JSON is read as JSON, and fails as JSON.
    let csv = b"x,y,z,dx,dy,dz,length,radius\n1,1,1,1,0,0,1,0.02\n";
    let out = rgc_with_input(
        &[
            "truth",
            "--rods",
            "-",
            "--rods-format",
            "json",
            "--box",
            "4",
        ],
        csv,
    );
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("rods JSON") && err.contains("standard input"),
        "{err}"
    );
    let out = rgc_with_input(&["truth", "--rods", "-", "--box", "4", "--json"], csv);
    assert_eq!(summary(&out)["n_rods"], 1);
}

#[test]
fn empty_standard_input_is_refused_naming_it() {
    let out = rgc_with_input(&["truth", "--rods", "-", "--box", "4"], b"");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("standard input"), "{err}");
}

#[test]
fn lammps_columns_are_refused_for_a_table_on_standard_input() {
    let csv = b"x,y,z,dx,dy,dz,length,radius\n1,1,1,1,0,0,1,0.02\n";
    let out = rgc_with_input(
        &[
            "truth",
            "--rods",
            "-",
            "--box",
            "4",
            "--lammps-columns",
            "dx=c_u[1]",
        ],
        csv,
    );
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--lammps-columns applies to LAMMPS dumps") && err.contains("rods CSV"),
        "{err}"
    );
}
