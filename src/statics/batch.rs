//! Independent solves on all cores: load-set batches, identification
//! multi-starts, the candidate fits of `axle diagnose`. Each worker thread
//! keeps its own [`Simulator`] (solver buffers reused across the jobs it
//! takes), and every job starts its paths without a predictor from another
//! job, so a job's result does not depend on which thread ran it or what it
//! ran before: the results are those of the serial run, in the jobs' order.
//!
//! Parallelism through rayon's global pool (all cores unless
//! `RAYON_NUM_THREADS` says otherwise); one job per task, so jobs should be
//! whole paths or fits, not single Newton steps.

use super::path::{PathRun, Simulator};
use super::{Problem, State};
use crate::model::PointLoad;
use rayon::prelude::*;

/// `f(simulator, job)` for every job, on all cores, results in the jobs' order.
///
/// `f` may build its own [`Problem`] (a candidate model) or share one; it
/// must not depend on the simulator's previous job (a [`Simulator`] never
/// carries a predictor from one path to the next).
pub fn map<J, R, F>(jobs: &[J], f: F) -> Vec<R>
where
    J: Sync,
    R: Send,
    F: Fn(&mut Simulator, &J) -> R + Sync,
{
    jobs.par_iter()
        .map_init(Simulator::new, |sim, job| f(sim, job))
        .collect()
}

/// [`map`] on the calling thread, one simulator for every job: the reference
/// the parallel run must equal, and the cheaper choice for a handful of jobs.
pub fn map_serial<J, R, F>(jobs: &[J], f: F) -> Vec<R>
where
    F: Fn(&mut Simulator, &J) -> R,
{
    let mut sim = Simulator::new();
    jobs.iter().map(|job| f(&mut sim, job)).collect()
}

/// One load path of a batch: its cases in order, and where it starts.
#[derive(Debug, Clone)]
pub struct PathJob {
    pub cases: Vec<Vec<PointLoad>>,
    pub start: State,
}

/// Every path of `jobs` on `problem`, on all cores (as [`Simulator::run`] each).
pub fn paths(problem: &Problem, jobs: &[PathJob]) -> Vec<PathRun> {
    map(jobs, |sim, j| sim.run(problem, &j.cases, &j.start, &[]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::statics::path::set_loads;
    use crate::statics::testkit::mcpherson;

    /// Jobs that differ: table 5-1 scaled by 0.65..1.0, from design and from
    /// the previous job's end, more jobs than threads.
    #[test]
    fn a_parallel_batch_gives_the_serial_results_bit_for_bit() {
        let m = mcpherson();
        let p = Problem::new(&m).expect("problem");
        let set = m.load_set_named("thesis_table_5_1").expect("set");
        let base = set_loads(&m, set).expect("loads");
        let design = State::design(&m);
        let warm = crate::statics::path::simulate(&p, &base, &design)
            .steps
            .pop()
            .expect("solves")
            .state;
        let jobs: Vec<PathJob> = (0..8)
            .map(|k| {
                let s = 0.65 + 0.05 * k as f64;
                let cases = base
                    .iter()
                    .map(|c| {
                        c.iter()
                            .map(|l| PointLoad {
                                force: l.force * s,
                                torque: l.torque * s,
                                ..*l
                            })
                            .collect()
                    })
                    .collect();
                let start = if k % 2 == 0 {
                    design.clone()
                } else {
                    warm.clone()
                };
                PathJob { cases, start }
            })
            .collect();
        let par = paths(&p, &jobs);
        let ser = map_serial(&jobs, |sim, j| sim.run(&p, &j.cases, &j.start, &[]));
        // and each job alone, with a fresh simulator
        let alone: Vec<PathRun> = jobs
            .iter()
            .map(|j| crate::statics::path::simulate(&p, &j.cases, &j.start))
            .collect();
        assert_eq!(par.len(), 8);
        for ((a, b), c) in par.iter().zip(&ser).zip(&alone) {
            assert!(a.failure.is_none(), "{:?}", a.failure);
            assert!(b.failure.is_none());
            assert_eq!(a.steps.len(), 13);
            for ((x, y), z) in a.steps.iter().zip(&b.steps).zip(&c.steps) {
                assert_eq!(x.state, y.state);
                assert_eq!(x.state, z.state);
                assert_eq!(
                    (x.iterations, x.factorizations),
                    (y.iterations, y.factorizations)
                );
                assert_eq!(x.residual.to_bits(), z.residual.to_bits());
            }
        }
        // the scale shows: the spring carries more load in the heavier jobs
        let z = |r: &PathRun| r.steps[4].state.part_pose(m.wheels[0].part).0.z;
        assert!(z(&par[0]) != z(&par[7]));
    }
}
