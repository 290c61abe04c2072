//! The traversal's pending children, nearest on top.

use super::{Node8, STACK, WIDTH};
use std::mem::MaybeUninit;

/// A pending child: where it is, and how far along the ray its box starts.
#[derive(Clone, Copy)]
pub(super) struct Entry {
    pub(super) child: u32,
    pub(super) count: u32,
    pub(super) t: f32,
}

/// The traversal stack. Its slots are left uninitialised: clearing a few kilobytes
/// per ray cost more than a tenth of the traversal time.
pub(super) struct Stack {
    items: [MaybeUninit<Entry>; STACK],
    pub(super) len: usize,
}

impl Stack {
    #[inline]
    pub(super) fn new(root: Entry) -> Stack {
        let mut stack = Stack::empty();
        stack.push(root);
        stack
    }

    #[inline]
    pub(super) fn empty() -> Stack {
        Stack {
            items: [const { MaybeUninit::uninit() }; STACK],
            len: 0,
        }
    }

    #[inline]
    pub(super) fn pop(&mut self) -> Option<Entry> {
        self.len = self.len.checked_sub(1)?;
        // SAFETY: slots below `len` were written by `push` or `push_sorted`.
        Some(unsafe { self.items.get_unchecked(self.len).assume_init() })
    }

    /// The entry [`Stack::pop`] would give next.
    #[inline(always)]
    pub(super) fn peek(&self) -> Option<Entry> {
        let top = self.len.checked_sub(1)?;
        // SAFETY: as in `pop`.
        Some(unsafe { self.items.get_unchecked(top).assume_init() })
    }

    #[inline]
    pub(super) fn push(&mut self, e: Entry) {
        debug_assert!(self.len < STACK);
        // SAFETY: a tree of at most MAX_DEPTH levels has at most seven entries a
        // level waiting beside the one entered, which STACK holds.
        unsafe { *self.items.get_unchecked_mut(self.len) = MaybeUninit::new(e) };
        self.len += 1;
    }

    /// Pushes the children of `node` in `mask` (bit `i` for child `i`), entered at
    /// `t[i]`, so the nearest is popped first.
    #[inline(always)]
    pub(super) fn push_children(&mut self, node: &Node8, mut mask: u32, t: &[f32; WIDTH]) {
        let base = self.len;
        while mask != 0 {
            let lane = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            self.push_sorted(node.entry(lane, t[lane]), base);
        }
    }

    /// Pushes the children of `node` in `mask` (at least two) as [`Stack::push_children`]
    /// does, and takes the nearest back off.
    #[inline(always)]
    pub(super) fn push_children_but_nearest(
        &mut self,
        node: &Node8,
        mask: u32,
        t: &[f32; WIDTH],
    ) -> Entry {
        self.push_children(node, mask, t);
        self.len -= 1;
        // SAFETY: the slot just written by `push_children`.
        unsafe { self.items.get_unchecked(self.len).assume_init() }
    }

    /// Pushes `e` among the entries above `base`, kept farthest first, so the nearest
    /// is popped next.
    #[inline]
    pub(super) fn push_sorted(&mut self, e: Entry, base: usize) {
        let mut i = self.len;
        while i > base {
            // SAFETY: base <= i - 1 < len, a written slot.
            let below = unsafe { self.items[i - 1].assume_init() };
            if below.t >= e.t {
                break;
            }
            // SAFETY: i <= len < STACK, as in `push`.
            unsafe { *self.items.get_unchecked_mut(i) = MaybeUninit::new(below) };
            i -= 1;
        }
        debug_assert!(self.len < STACK);
        // SAFETY: as above.
        unsafe { *self.items.get_unchecked_mut(i) = MaybeUninit::new(e) };
        self.len += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entry(child: u32, t: f32) -> Entry {
        Entry { child, count: 0, t }
    }

    /// What `peek` shows is what `pop` then gives, nearest first, down to an empty
    /// stack, where both give nothing.
    #[test]
    fn peek_shows_what_pop_gives_next() {
        let mut stack = Stack::new(entry(0, 0.0));
        let base = stack.len;
        for (child, t) in [(1, 3.0), (2, 1.0), (3, 2.0)] {
            stack.push_sorted(entry(child, t), base);
        }
        let mut popped = Vec::new();
        while let Some(next) = stack.peek() {
            let e = stack.pop().expect("peek saw an entry");
            assert_eq!((next.child, next.t), (e.child, e.t));
            popped.push(e.child);
        }
        assert_eq!(popped, [2, 3, 1, 0]);
        assert!(stack.pop().is_none());
    }
}
