//! Evaluating and building side by side: the evaluator hands its items
//! over in parts (a run of whole statements, or a few thousand steps of a
//! loop), and the builder reads each part on a thread of its own while
//! the evaluator makes the next. The builder sees the same parts in the
//! same order as when it ran in between, so the scene, its mistakes and
//! its warnings are the same; on two cores the wall time of a long loop
//! is the slower of the two stages instead of their sum (`many.rt`: its
//! 100,000 spheres and 10,000 placements).
//!
//! Each part goes back to the evaluator once built, to be freed on the
//! thread that allocated it: a block freed on another thread goes back to
//! its arena under that arena's lock, which the evaluator is taking at
//! the same time for its next part's blocks, and on a machine whose two
//! threads sit on distant cores that lock and the freed blocks' cache
//! lines shuttle between them for every block.

use super::Builder;
use crate::eval::{Options, TopLevel};
use crate::lang::ast::Item;
use crate::lang::diagnostics::Error;
use std::sync::mpsc;

/// Parts evaluated but not yet built: enough that neither side waits on
/// the other's unevenness, few enough that a long loop's items never all
/// exist at once (a part is at most 256 items).
const PARTS_IN_FLIGHT: usize = 8;

/// A part, with the names bound so far when they changed since the last
/// part (the builder's suggestions for unknown names).
type Part = (Vec<Item>, Option<Vec<String>>);

/// Evaluates `b`'s program and builds each part into `b` as it comes;
/// gives the evaluator's errors and top-level values.
pub(super) fn evaluate_and_build(
    b: &mut Builder<'_>,
    options: &Options,
) -> (Vec<Error>, Vec<TopLevel>) {
    let program = b.program;
    let transfer = b.scene.settings.transfer;
    let mut known_len = b.env.known.len();
    let threaded = std::thread::scope(|s| {
        let (tx, rx) = mpsc::sync_channel::<Part>(PARTS_IN_FLIGHT);
        let (built_tx, built) = mpsc::channel::<Vec<Item>>();
        let on_thread = &mut *b;
        // Building recurses as deep as the blocks nest: a main thread's
        // stack, not a spawned thread's 2 MiB.
        let spawned = std::thread::Builder::new()
            .name("rt-build".into())
            .stack_size(8 << 20)
            .spawn_scoped(s, move || {
                for (items, known) in rx {
                    if let Some(known) = known {
                        on_thread.env.known = known;
                    }
                    on_thread.top_level(&items);
                    // An evaluator that has finished frees what is left
                    // after the join; one that has panicked, nothing.
                    let _ = built_tx.send(items);
                }
            });
        // No thread to be had (the system's limit): build in between
        // instead, below, rather than fail.
        let Ok(builder) = spawned else {
            return None;
        };
        let out =
            crate::eval::evaluate_in_parts_bound(program, transfer, options, |items, known| {
                built.try_iter().for_each(drop);
                let changed = known.len() != known_len;
                known_len = known.len();
                // A builder that panicked has hung up: its panic is raised
                // by the join below.
                let _ = tx.send((items, changed.then(|| known.to_vec())));
            });
        drop(tx);
        if let Err(panic) = builder.join() {
            std::panic::resume_unwind(panic);
        }
        built.try_iter().for_each(drop);
        Some(out)
    });
    threaded.unwrap_or_else(|| {
        crate::eval::evaluate_in_parts_bound(program, transfer, options, |items, known| {
            if b.env.known.len() != known.len() {
                b.env.known = known.to_vec();
            }
            b.top_level(&items);
        })
    })
}
