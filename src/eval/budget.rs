//! The evaluation's budgets: every expression and item takes a step, every
//! object counts against the object limit, and the cancel flag is looked
//! at every 4096 steps; past a limit the evaluation reports it once and
//! stops.

use super::*;

impl<'p> Expander<'p> {
    /// Takes a step, the evaluation's own or an expression's, or reports
    /// the budget spent (once) and says to stop.
    pub(super) fn step(&self, span: Span, errors: &mut Vec<Error>) -> bool {
        // The common case (no cancel check due, budget left) is kept apart
        // from the rest, whose message building made each call save and
        // restore registers.
        self.take_steps(1) || (!self.stopped.get() && self.step_checked(span, errors))
    }

    /// `k` steps (k ≥ 1) at once, where [`Expander::step`] would take
    /// each of them without a check: the evaluation not stopped, no cancel
    /// look due before any of them (the count not a multiple of 4096),
    /// the budget not passed by the last; false, with nothing taken,
    /// otherwise. [`fast::value`] takes its expression's steps so.
    #[inline(always)]
    pub(super) fn take_steps(&self, k: u64) -> bool {
        let n = self.steps.get();
        let into = n % 4096;
        if self.stopped.get() || into == 0 || k > 4096 - into {
            return false;
        }
        match n.checked_add(k) {
            Some(end) if end <= self.options.limits.steps => {
                self.steps.set(end);
                true
            }
            _ => false,
        }
    }

    /// [`Expander::step`] for an item, whose span (which a loop's items
    /// work out from their first and last) is only wanted for a message.
    pub(super) fn step_item(&self, item: &Item, errors: &mut Vec<Error>) -> bool {
        self.take_steps(1) || self.step(item.span(), errors)
    }

    /// [`Expander::step`] when the cancel flag is due a look or the budget
    /// may be spent.
    #[cold]
    #[inline(never)]
    pub(super) fn step_checked(&self, span: Span, errors: &mut Vec<Error>) -> bool {
        // Looked at once every 4096 steps: the load is not free.
        if self.steps.get().is_multiple_of(4096)
            && let Some(c) = &self.options.cancel
            && c.load(std::sync::atomic::Ordering::Relaxed)
        {
            self.stopped.set(true);
            return false;
        }
        let limit = self.options.limits.steps;
        self.within(&self.steps, limit, errors, || {
            Error::new(
                span,
                format!("the scene program ran for more than {limit} evaluation steps"),
            )
            .label("still running here")
            .help("look for a loop or recursion that does more than meant, or raise the limit with `--max-steps N`")
        })
    }

    /// Counts one more against a budget; past `limit`, reports `error` once
    /// and stops all further evaluation.
    pub(super) fn within(
        &self,
        counter: &Cell<u64>,
        limit: u64,
        errors: &mut Vec<Error>,
        error: impl FnOnce() -> Error,
    ) -> bool {
        let n = counter.get() + 1;
        counter.set(n);
        if n > limit {
            self.stop(errors, error());
            return false;
        }
        true
    }

    /// Reports a limit once and stops all further evaluation.
    pub(super) fn stop(&self, errors: &mut Vec<Error>, e: Error) {
        if !self.stopped.replace(true) {
            errors.push(self.traced(e));
        }
    }

    pub(super) fn count_object(&self, span: Span, errors: &mut Vec<Error>) -> bool {
        let limit = self.options.limits.objects;
        self.within(&self.objects, limit, errors, || {
            Error::new(span, format!("the scene makes more than {limit} objects"))
                .label("one too many")
                .help("raise the limit with `--max-objects N` if this is meant")
        })
    }
}
