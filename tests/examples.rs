//! Every example and stdlib module checks clean, is a formatter fixed point, and
//! prints back (model → source) to a model that prints the same.

use axle::check::check_str;
use axle::diagnostic::render;

fn check_clean(path: &std::path::Path) -> (String, axle::model::Model) {
    let text = std::fs::read_to_string(path).expect("readable");
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let (sources, checked) = check_str(&name, &text);
    let rendered: String = checked
        .problems
        .list
        .iter()
        .map(|d| render::to_string(&sources, d))
        .collect();
    assert!(
        checked.problems.list.is_empty(),
        "{name} has diagnostics:\n{rendered}"
    );
    (text, checked.model.expect("no errors means a model"))
}

fn each(dir: &str, f: impl Fn(&std::path::Path)) {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(dir);
    let mut paths: Vec<_> = std::fs::read_dir(&root)
        .expect("directory exists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "axle"))
        .collect();
    paths.sort();
    assert!(!paths.is_empty(), "no .axle files in {dir}");
    for p in paths {
        f(&p);
    }
}

#[test]
fn examples_and_stdlib_check_clean() {
    each("examples", |p| {
        check_clean(p);
    });
    each("stdlib", |p| {
        check_clean(p);
    });
}

#[test]
fn examples_and_stdlib_are_formatter_fixed_points() {
    for dir in ["examples", "stdlib"] {
        each(dir, |p| {
            let text = std::fs::read_to_string(p).expect("readable");
            let formatted = axle::fmt::format_source(axle::span::FileId(0), &text).expect("parses");
            assert_eq!(
                formatted,
                text,
                "{} is not in canonical format (run `axle fmt`)",
                p.display()
            );
        });
    }
}

#[test]
fn printed_models_check_and_print_the_same() {
    each("examples", |p| {
        let (_, model) = check_clean(p);
        let printed = axle::fmt::print_model(&model);
        let (sources, again) = check_str("printed.axle", &printed);
        let rendered: String = again
            .problems
            .list
            .iter()
            .map(|d| render::to_string(&sources, d))
            .collect();
        let again = again.model.unwrap_or_else(|| {
            panic!(
                "{}: printed model does not check:\n{rendered}\n{printed}",
                p.display()
            )
        });
        assert_eq!(axle::fmt::print_model(&again), printed, "{}", p.display());
        // Same elements and the same numbers (to printing precision).
        assert_eq!(again.markers.len(), model.markers.len());
        assert_eq!(again.bushings.len(), model.bushings.len());
        for (a, b) in again.markers.iter().zip(&model.markers) {
            assert!((a.origin() - b.origin()).norm() < 1e-9);
            assert!(
                (a.rotation - b.rotation).abs().max() < 1e-9,
                "{} {}",
                p.display(),
                a.name
            );
        }
        for (a, b) in again.load_sets.iter().zip(&model.load_sets) {
            assert_eq!(a.cases.len(), b.cases.len());
            for (x, y) in a.cases.iter().zip(&b.cases) {
                assert_eq!(x.name, y.name);
                for (u, v) in x.values.iter().zip(&y.values) {
                    assert!((u - v).abs() < 1e-9);
                }
            }
        }
    });
}
