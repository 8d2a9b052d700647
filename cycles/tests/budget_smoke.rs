use alvs_cycles::budget::{build_firmware, run_scene, worst_cases, Bench};
use std::path::Path;

#[test]
fn smoke() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let elf = std::fs::read(build_firmware(root).unwrap()).unwrap();
    let mut b = Bench::new(&elf).unwrap();
    for s in worst_cases() {
        let t = std::time::Instant::now();
        let r = run_scene(&mut b, &s).unwrap();
        println!(
            "{} worst {:?} at {} mean {} afs {} stack {} in {:?}",
            r.name,
            r.worst,
            r.worst_frame,
            r.mean_pessimistic,
            r.max_afs,
            r.stack,
            t.elapsed()
        );
    }
}
