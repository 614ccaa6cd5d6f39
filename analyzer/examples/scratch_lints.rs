use hipop_analyzer::*;
fn main() {
    let c = std::env::var("DIR").unwrap_or("/tmp/big5/".into());
    let d = std::fs::read_to_string(format!("{c}domain.pddl")).unwrap();
    let p = std::fs::read_to_string(format!("{c}problem.pddl")).unwrap();
    let mut host = AnalysisHost::new();
    host.set_file_text("d.pddl", d.as_str());
    let f = host.set_file_text("p.pddl", p.as_str());
    let a = host.analysis();
    a.check_diagnostics(f).unwrap();
    let t = std::time::Instant::now();
    let n = a.diagnostics(f).unwrap().len();
    eprintln!("lints {:?} ({n} diagnostics)", t.elapsed());
}
