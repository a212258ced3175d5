//! Data safety through the built binary: no command writes onto one of its
//! inputs (same path, a symbolic link, a hard link), writes are atomic (a
//! write killed half-way leaves the old file whole), `-` is stdin or
//! stdout, and a failing stdout is a non-zero exit with a message.

mod common;
use common::axle;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// A fresh folder of the test target's scratch space with a copy of the McPherson.
fn folder(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("writes_{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    std::fs::copy("examples/mcpherson.axle", dir.join("m.axle")).expect("copy");
    dir
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// Runs `args`, asserts exit 2 with the refusal message and `victim` unchanged.
fn refused(args: &[&str], victim: &Path) {
    let before = std::fs::read(victim).expect("victim exists");
    let (code, _, stderr) = axle(args);
    assert_eq!(code, 2, "{args:?}: {stderr}");
    assert!(stderr.contains("refusing to write"), "{args:?}: {stderr}");
    assert_eq!(
        std::fs::read(victim).expect("still there"),
        before,
        "{args:?}"
    );
}

#[test]
fn no_command_writes_onto_its_own_inputs() {
    let dir = folder("inputs");
    let m = dir.join("m.axle");
    let adm = dir.join("annexe_f.adm");
    std::fs::copy("tests/data/adams/annexe_f.adm", &adm).expect("copy deck");
    let csv = dir.join("landmarks.csv");
    std::fs::write(&csv, "step,part,landmark,x,y,z\n").expect("csv");
    let (m, adm, csv) = (s(&m), s(&adm), s(&csv));
    refused(&["emit", "adm", m, "-o", m], m.as_ref());
    refused(&["emit", "lcf", m, "-o", m], m.as_ref());
    refused(&["solve", m, "-o", m], m.as_ref());
    refused(&["solve", m, "--loads", csv, "-o", csv], csv.as_ref());
    refused(
        &["kc", m, "--sweep", "thesis_table_5_1", "-o", m],
        m.as_ref(),
    );
    refused(
        &["kc", m, "--sweep", "thesis_table_5_1", "--plot", m],
        m.as_ref(),
    );
    refused(&["import", "adm", adm, "-o", adm], adm.as_ref());
    refused(&["locate", m, "--landmarks", csv, "-o", csv], csv.as_ref());
    refused(&["locate", m, "--landmarks", csv, "-o", m], m.as_ref());
    refused(
        &["correct", m, "--landmarks", csv, "--case", "c1", "-o", m],
        m.as_ref(),
    );
    refused(
        &[
            "identify",
            m,
            "--landmarks",
            csv,
            "--method",
            "direct",
            "-o",
            csv,
        ],
        csv.as_ref(),
    );
}

#[cfg(unix)]
#[test]
fn an_input_reached_through_a_link_is_refused_too() {
    let dir = folder("links");
    let m = dir.join("m.axle");
    let soft = dir.join("soft.axle");
    let hard = dir.join("hard.axle");
    std::os::unix::fs::symlink(&m, &soft).expect("symlink");
    std::fs::hard_link(&m, &hard).expect("hard link");
    let dotted = dir.join(".").join("m.axle");
    refused(&["emit", "adm", s(&m), "-o", s(&soft)], &m);
    refused(&["emit", "adm", s(&m), "-o", s(&hard)], &m);
    refused(&["emit", "adm", s(&soft), "-o", s(&dotted)], &m);
    refused(&["solve", s(&hard), "-o", s(&m)], &m);
}

#[test]
fn a_new_output_is_written_whole_and_no_temporary_file_is_left() {
    let dir = folder("fresh");
    let out = dir.join("m.adm");
    let (code, stdout, stderr) = axle(&["emit", "adm", s(&dir.join("m.axle")), "-o", s(&out)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.is_empty());
    let (_, to_stdout, _) = axle(&["emit", "adm", s(&dir.join("m.axle")), "-o", "-"]);
    assert_eq!(std::fs::read_to_string(&out).expect("written"), to_stdout);
    let names: Vec<String> = std::fs::read_dir(&dir)
        .expect("folder")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
}

#[cfg(unix)]
#[test]
fn a_read_only_output_is_not_replaced() {
    let dir = folder("readonly");
    let out = dir.join("deck.adm");
    std::fs::write(&out, "keep me\n").expect("write");
    let mut p = std::fs::metadata(&out).expect("meta").permissions();
    p.set_readonly(true);
    std::fs::set_permissions(&out, p).expect("chmod");
    let (code, _, stderr) = axle(&["emit", "adm", s(&dir.join("m.axle")), "-o", s(&out)]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("read-only"), "{stderr}");
    assert_eq!(std::fs::read_to_string(&out).expect("read"), "keep me\n");
}

/// `fmt` killed half-way through its write (here by the file-size limit,
/// SIGXFSZ, as a full disk or a kill would stop it) leaves the source whole.
#[cfg(unix)]
#[test]
fn fmt_killed_during_its_write_leaves_the_source_whole() {
    let dir = folder("killed");
    let src = dir.join("messy.axle");
    // Valid, unformatted, and larger than the 1-block (512 bytes) limit.
    let text = std::fs::read_to_string("examples/mcpherson.axle")
        .expect("example")
        .replace("    ", "      ");
    std::fs::write(&src, &text).expect("write");
    let status = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -f 1; exec '{}' fmt '{}'",
            env!("CARGO_BIN_EXE_axle"),
            s(&src)
        ))
        .stderr(Stdio::null())
        .status()
        .expect("sh runs");
    assert!(!status.success());
    assert_eq!(std::fs::read_to_string(&src).expect("source"), text);
}

/// `solve --format json` writes a long path while it solves it (in pieces,
/// not as one text at the end), through the same atomic write: the file
/// is whole, the same as stdout, no temporary file is left, and a write
/// killed after its first pieces (the file-size limit, SIGXFSZ) leaves the
/// old file whole.
#[cfg(unix)]
#[test]
fn a_long_path_written_as_it_is_solved_replaces_its_output_whole() {
    let dir = folder("streamed");
    let mut loads = String::from("step,fx,fy,fz\n");
    for k in 0..60 {
        loads += &format!("{},0,{},{}\n", k + 1, 20 * k, 2000 + 50 * k);
    }
    std::fs::write(dir.join("loads.csv"), loads).expect("loads");
    let out = dir.join("out.json");
    std::fs::write(&out, "keep me\n").expect("write");
    let args = |o: &str| {
        let (m, l) = (dir.join("m.axle"), dir.join("loads.csv"));
        format!(
            "'{}' solve '{}' --loads '{}' --format json -o '{o}'",
            env!("CARGO_BIN_EXE_axle"),
            s(&m),
            s(&l)
        )
    };
    // 200 blocks of 512 bytes: room for three of the 64 KiB pieces, not for
    // the document of about 400 KiB.
    let status = Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -f 200; exec {}", args(s(&out))))
        .stderr(Stdio::null())
        .status()
        .expect("sh runs");
    assert!(!status.success());
    assert_eq!(std::fs::read_to_string(&out).expect("kept"), "keep me\n");
    // A kill runs no clean-up: the killed run's temporary file (named by its
    // process, so no other run meets it) is left beside the target.
    let temporary = || -> Vec<PathBuf> {
        let entries = std::fs::read_dir(&dir).expect("folder");
        let paths = entries.map(|e| e.expect("entry").path());
        paths.filter(|p| s(p).ends_with(".axle-tmp")).collect()
    };
    let killed = temporary();
    assert_eq!(killed.len(), 1, "{killed:?}");
    std::fs::remove_file(&killed[0]).expect("removed");
    let (code, stdout, stderr) = axle(&[
        "solve",
        s(&dir.join("m.axle")),
        "--loads",
        s(&dir.join("loads.csv")),
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.len() > 300_000, "{} bytes", stdout.len());
    let doc: serde_json::Value = serde_json::from_str(&stdout).expect("one JSON document");
    assert_eq!(doc["cases"].as_array().map(Vec::len), Some(60));
    let status = Command::new("sh")
        .arg("-c")
        .arg(format!("exec {}", args(s(&out))))
        .status()
        .expect("sh runs");
    assert!(status.success());
    assert_eq!(std::fs::read_to_string(&out).expect("written"), stdout);
    assert_eq!(temporary(), Vec::<PathBuf>::new());
}

fn run_with(args: &[&str], stdin: &[u8], stdout: Stdio) -> (Option<i32>, String, String) {
    use std::io::Write;
    let mut child = Command::new(env!("CARGO_BIN_EXE_axle"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdin(Stdio::piped())
        .stdout(stdout)
        .stderr(Stdio::piped())
        .spawn()
        .expect("runs");
    child
        .stdin
        .take()
        .expect("stdin")
        .write_all(stdin)
        .expect("feeds stdin");
    let out = child.wait_with_output().expect("finishes");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!stderr.contains("panicked"), "{stderr}");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr,
    )
}

#[test]
fn dash_reads_stdin_and_writes_stdout() {
    let text = std::fs::read("examples/four_bar.axle").expect("example");
    let (code, stdout, stderr) = run_with(&["emit", "adm", "-", "-o", "-"], &text, Stdio::piped());
    assert_eq!(code, Some(0), "{stderr}");
    let (_, from_file, _) = axle(&["emit", "adm", "examples/four_bar.axle"]);
    assert_eq!(stdout, from_file);
    // Diagnostics name the stream.
    let (code, _, stderr) = run_with(&["check", "-"], b"part p {", Stdio::piped());
    assert_eq!(code, Some(1));
    assert!(stderr.contains("<stdin>:1:"), "{stderr}");
    // `fmt -` formats stdin to stdout and touches no file.
    let (code, stdout, _) = run_with(&["fmt", "-"], &text, Stdio::piped());
    assert_eq!(code, Some(0));
    let (_, again, _) = run_with(&["fmt", "-"], stdout.as_bytes(), Stdio::piped());
    assert_eq!(again, stdout);
}

#[cfg(target_os = "linux")]
#[test]
fn a_full_stdout_is_an_error_with_a_message_not_a_panic() {
    for args in [
        &["check", "--format", "json", "examples/mcpherson.axle"][..],
        &["solve", "examples/four_bar.axle", "--format", "json"][..],
        &["emit", "adm", "examples/mcpherson.axle"][..],
    ] {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .expect("/dev/full");
        let (code, _, stderr) = run_with(args, b"", Stdio::from(full));
        assert_eq!(code, Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains("cannot write to stdout"), "{stderr}");
    }
}

#[test]
fn check_json_reports_an_unreadable_file_as_a_diagnostic() {
    let (code, stdout, _) = axle(&["check", "--format", "json", "no/such/file.axle"]);
    assert_eq!(code, 2);
    let v: serde_json::Value = serde_json::from_str(&stdout).expect("one JSON document");
    let d = &v["diagnostics"][0];
    assert_eq!(d["code"], "E0003");
    assert_eq!(d["file"], "no/such/file.axle");
    assert!(
        d["message"].as_str().expect("text").contains("cannot read"),
        "{d}"
    );
}

#[test]
fn a_byte_that_is_not_utf8_is_a_diagnostic_at_its_line_and_column() {
    let dir = folder("utf8");
    let bad = dir.join("bad.axle");
    std::fs::write(&bad, b"ground g {\n    marker o\xff at (0, 0, 0) mm\n}\n").expect("write");
    let (code, _, stderr) = axle(&["check", s(&bad)]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("E0002"), "{stderr}");
    assert!(stderr.contains("bad.axle:2:13"), "{stderr}");
    let csv = dir.join("loads.csv");
    std::fs::write(&csv, b"step,fz\n1,10\xe9\n").expect("write");
    let (code, _, stderr) = axle(&["solve", "examples/four_bar.axle", "--loads", s(&csv)]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("loads.csv:2:5"), "{stderr}");
}
