//! The evaluation's budgets: every expression and item takes a step, every
//! object counts against the object limit, and the cancel flag is looked
//! at every 4096 steps; past a limit the evaluation reports it once and
//! stops.

use super::*;

impl<'p> Expander<'p> {
    pub(super) fn step(&self, span: Span, errors: &mut Vec<Error>) -> bool {
        if self.stopped.get() {
            return false;
        }
        // Every expression and item takes a step: the common case (no
        // cancel check due, budget left) is kept apart from the rest, whose
        // message building made each call save and restore registers.
        let n = self.steps.get();
        if !n.is_multiple_of(4096) && n < self.options.limits.steps {
            self.steps.set(n + 1);
            return true;
        }
        self.step_checked(span, errors)
    }

    /// `k` steps at once, for [`fast::value`], when [`Expander::step`]
    /// would take each of them without a check (no cancel look due, the
    /// budget not reached): false, with nothing taken, otherwise.
    pub(super) fn take_steps(&self, k: u64) -> bool {
        let n = self.steps.get();
        let room = 4096 - n % 4096;
        if self.stopped.get() || n.is_multiple_of(4096) || k >= room {
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
        let n = self.steps.get();
        if !self.stopped.get() && !n.is_multiple_of(4096) && n < self.options.limits.steps {
            self.steps.set(n + 1);
            return true;
        }
        self.step(item.span(), errors)
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
