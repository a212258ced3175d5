//! Every file under `tests/fail/` holds one mistake; its snapshot shows the
//! source and the diagnostics a user sees (see tests/README.md).

use axle::check::check_file;
use axle::diagnostic::render;
use axle::source::SourceMap;

#[test]
fn every_mistake_gets_a_diagnostic() {
    insta::glob!("fail", "**/*.axle", |path| {
        let text = std::fs::read_to_string(path).expect("fixture is readable");
        let rel = path
            .strip_prefix(env!("CARGO_MANIFEST_DIR"))
            .unwrap_or(path)
            .to_string_lossy()
            .replace('\\', "/");
        let mut sources = SourceMap::new();
        let id = sources.add(rel.clone(), text.clone());
        let checked = check_file(&mut sources, id);
        assert!(
            !checked.problems.list.is_empty(),
            "{rel}: the mistake went unreported"
        );
        let rendered: String = checked
            .problems
            .list
            .iter()
            .map(|d| render::to_string(&sources, d))
            .collect();
        insta::assert_snapshot!(format!("----- SOURCE\n{text}----- DIAGNOSTICS\n{rendered}"));
    });
}
