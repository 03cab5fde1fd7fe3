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
use crate::eval::{Options, Sink, TopLevel};
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
    let known_len = b.env.known.len();
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
                    // Once the evaluator has finished (or panicked), the
                    // last few parts are freed here.
                    let _ = built_tx.send(items);
                }
            });
        // No thread to be had (the system's limit): build in between
        // instead, below, rather than fail.
        let Ok(builder) = spawned else {
            return None;
        };
        let mut sink = ToBuilder {
            tx,
            built: Some(built),
            known_len,
        };
        let out = crate::eval::evaluate_into(program, transfer, options, &mut sink);
        drop(sink);
        if let Err(panic) = builder.join() {
            std::panic::resume_unwind(panic);
        }
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

/// The evaluator's end of the pipeline: sends parts, and frees the parts
/// the builder sends back one loop iteration at a time (see
/// [`Sink::recycler`]).
struct ToBuilder {
    tx: mpsc::SyncSender<Part>,
    built: Option<mpsc::Receiver<Vec<Item>>>,
    known_len: usize,
}

impl Sink for &mut ToBuilder {
    fn part(&mut self, items: Vec<Item>, known: &[String]) {
        let changed = known.len() != self.known_len;
        self.known_len = known.len();
        // A builder that panicked has hung up: its panic is raised by the
        // join.
        let _ = self.tx.send((items, changed.then(|| known.to_vec())));
    }

    fn recycler(&mut self) -> Option<Box<dyn FnMut()>> {
        let built = self.built.take()?;
        let mut used: Vec<Item> = Vec::new();
        Some(Box::new(move || {
            if used.is_empty() {
                match built.try_recv() {
                    Ok(part) => used = part,
                    Err(_) => return,
                }
            }
            free_one(&mut used);
        }))
    }
}

/// Frees the last of `items`' innermost loop iterations (or, once a loop
/// item is empty, the item itself): as much as one iteration made, in
/// the order the allocator's per-thread cache gives it back.
fn free_one(items: &mut Vec<Item>) {
    if let Some(Item::Traced { items: inner, .. }) = items.last_mut()
        && matches!(inner.last(), Some(Item::Traced { .. }))
    {
        return free_one(inner);
    }
    items.pop();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Transfer;

    fn traced(items: &[Item]) -> usize {
        items
            .iter()
            .map(|i| match i {
                Item::Traced { items, .. } => 1 + traced(items),
                _ => 0,
            })
            .sum()
    }

    /// Each call frees one loop iteration, innermost and last first (an
    /// outer iteration once its inner ones are gone), and a statement's
    /// item whole: as many calls as iterations free a loop's part.
    #[test]
    fn free_one_frees_one_innermost_iteration_at_a_time() {
        let _watchdog = crate::watchdog::start();
        let src = "for i in 0..3 { for j in 0..4 { sphere { } } }\ncamera { }";
        let p =
            crate::lang::load_text(std::path::Path::new("scene.rt"), src.into()).expect("parses");
        let mut items = crate::eval::evaluate(&p, Transfer::Srgb, &Options::default()).items;
        assert_eq!((items.len(), traced(&items)), (5, 15));
        // The camera is a statement's two items (its word and its block):
        // each freed whole, at once.
        free_one(&mut items);
        free_one(&mut items);
        assert_eq!((items.len(), traced(&items)), (3, 15));
        for left in (0..15).rev() {
            free_one(&mut items);
            assert_eq!(traced(&items), left);
            if let Some(Item::Traced { items: outer, .. }) = items.last() {
                // The last outer iteration loses its inner ones first.
                assert!(traced(outer) < 4 || left % 5 == 0, "{left}");
            }
        }
        assert!(items.is_empty());
    }
}
