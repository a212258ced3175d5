//! The sparse LU's work on a fixed structure compiled to straight-line
//! machine code (x86-64): a refactorisation plan ([`super::refactor::Plan`])
//! and the two substitutions of a solve ([`super::pivoting::Rows`]).
//!
//! The plan is a list of products `(L entry, U entry)` and, per entry of the
//! factors, the matrix slot it starts from and how many products it
//! subtracts. Run as a loop, each product reads its two indices from the
//! list before the two values, and each entry's short loop ends on a branch
//! whose count changes from entry to entry: about 1 ns a product on the
//! McPherson. The same products written out as code, every index a
//! constant displacement (Gustavson's "loop-free code" for a sparse
//! elimination repeated on one structure, 1972), take two loads, a multiply
//! and a subtract each and no branch: the McPherson's 1 346 products ran in
//! 0.73 µs so written (by rustc, in a scratch program) against the loop's
//! 1.3, and the 500-case path takes 8 % less (`docs/performance.md`). The arithmetic is the plan's to the
//! bit: the same products in the same order, each rounded as Rust rounds
//! `acc - l * u` (SSE2 scalar, no fused product), the same pivot test and
//! `1 / pivot`. The substitutions likewise: a row's products in the loop's
//! order, each `y[column] * value` as constants' displacements.
//!
//! Compiling costs about as much as tens of runs save, and many structures
//! (a solve from the design, an identification's trial) are factorised
//! only a few times, so the loop runs a structure's first
//! [`COMPILE_AFTER`] times and the code the rest ([`Tiered`]).

use super::x86::{Asm, Base, Executable, Jump, Op, Writable, Xmm};
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU32, Ordering};

/// How many times a structure's work runs as a loop before it is compiled:
/// compiling the McPherson's plan costs 60-100 µs here (mostly the fresh
/// pages), what 100-160 runs save, so a structure that has run this often
/// and runs as often again repays it (`docs/performance.md`).
pub(crate) const COMPILE_AFTER: u32 = 128;

/// Code compiled on the [`COMPILE_AFTER`]th use, shared by whoever shares
/// the structure (on any thread).
#[derive(Debug)]
pub(crate) struct Tiered<T> {
    uses: AtomicU32,
    code: OnceLock<Option<T>>,
}

impl<T> Default for Tiered<T> {
    fn default() -> Self {
        Tiered {
            uses: AtomicU32::new(0),
            code: OnceLock::new(),
        }
    }
}

impl<T> Tiered<T> {
    /// The code, compiling it by `compile` if this use is the
    /// [`COMPILE_AFTER`]th; None before, or if it was not compiled (the
    /// caller runs the loop).
    #[inline]
    pub fn get(&self, compile: impl FnOnce() -> Option<T>) -> Option<&T> {
        if let Some(code) = self.code.get() {
            return code.as_ref();
        }
        if self.uses.fetch_add(1, Ordering::Relaxed) < COMPILE_AFTER {
            return None;
        }
        self.now(compile).as_ref()
    }

    /// The code compiled now by `compile` (once: later calls return the
    /// first's result).
    fn now(&self, compile: impl FnOnce() -> Option<T>) -> &Option<T> {
        self.code.get_or_init(compile)
    }

    /// Whether the code was compiled.
    #[cfg(test)]
    pub fn is_compiled(&self) -> bool {
        matches!(self.code.get(), Some(Some(_)))
    }
}

/// The generated function's arguments (System V): the matrix's values, L's
/// and U's values, the pivots' reciprocals, and five constants
/// ([`CompiledPlan::run`]).
const VALUES: Base = Base::Rdi;
const L: Base = Base::Rsi;
const U: Base = Base::Rdx;
const U_INV: Base = Base::Rcx;
const CONSTANTS: Base = Base::R8;

/// The constants' places: the sign bit's complement (an absolute value's
/// mask), 1, the pivot threshold, infinity, 0.
const ABS_MASK: usize = 0;
const ONE: usize = 1;
const THRESHOLD: usize = 2;
const INFINITY: usize = 3;
const ZERO: usize = 4;

/// The registers: an entry's sum, a product, the column's largest L entry,
/// scratch, the pivot and its reciprocal, the pivot's absolute value, and the
/// two constants kept in registers.
const SUM: Xmm = Xmm(0);
const PRODUCT: Xmm = Xmm(1);
const BIG: Xmm = Xmm(2);
const SCRATCH: Xmm = Xmm(3);
const PIVOT: Xmm = Xmm(4);
const PIVOT_ABS: Xmm = Xmm(5);
const ONE_REG: Xmm = Xmm(6);
const MASK_REG: Xmm = Xmm(7);

/// The plans compiled: those up to this many products. A larger plan's code
/// outgrows the first-level caches (about 20 bytes a product), and the
/// loop, whose few instructions stay cached, is as quick
/// (`docs/performance.md`).
pub(crate) const MAX_PRODUCTS: usize = 4096;

/// A plan's products as machine code, and the least lengths of the arrays it
/// reads and writes (every displacement in the code is below them).
#[derive(Debug)]
pub(crate) struct CompiledPlan {
    code: Executable,
    values_need: usize,
    l_need: usize,
    u_need: usize,
    columns: usize,
}

/// The plan's structure in the factors' terms: per column, the U entries
/// `u_ptr[j]..u_ptr[j + 1]` (the pivot last) and the L entries below the
/// unit diagonal `l_ptr[j] + 1..l_ptr[j + 1]`; per entry in that order, its
/// matrix slot (or `fill`) and its count of products; the products.
pub(crate) struct Structure<'a> {
    pub u_ptr: &'a [usize],
    pub l_ptr: &'a [usize],
    pub entries: &'a [(u32, u32)],
    pub products: &'a [(u32, u32)],
    pub fill: u32,
}

impl CompiledPlan {
    /// The plan `s` as code; None if it has more than [`MAX_PRODUCTS`]
    /// products, an index too large for a 32-bit displacement, entries
    /// that do not match its columns, or if the system gives no executable
    /// memory.
    pub fn new(s: &Structure) -> Option<CompiledPlan> {
        if s.products.len() > MAX_PRODUCTS || s.u_ptr.len() != s.l_ptr.len() {
            return None;
        }
        let columns = s.u_ptr.len().checked_sub(1)?;
        // At most 20 bytes a product (two loads or multiplications of 8,
        // a subtraction of 4), 16 an entry (its start and store) and 36
        // more an L entry (its largest, its scaling), 96 a column (the
        // pivot's test and reciprocal), and 16 for the last instruction's
        // scratch ([`Asm`]), written straight into the pages it will run
        // from (each fresh page costs about 2.5 µs here).
        let l_entries = s.l_ptr[columns]
            .checked_sub(s.l_ptr[0])?
            .checked_sub(columns)?;
        let bound =
            s.products.len() * 20 + s.entries.len() * 16 + l_entries * 36 + columns * 96 + 64;
        let mut pages = Writable::new(bound)?;
        let mut a = Asm::new(pages.bytes());
        a.mem(Op::Load, MASK_REG, CONSTANTS, ABS_MASK);
        a.mem(Op::Load, ONE_REG, CONSTANTS, ONE);
        let (mut values_need, mut l_need, mut u_need) = (0, 0, 0);
        let (mut entries, mut products) = (s.entries.iter(), s.products);
        // One entry: its start, minus its products, stored at `target[at]`.
        let mut entry = |a: &mut Asm, target: Base, at: usize| -> Option<()> {
            let &(from, count) = entries.next()?;
            let (now, rest) = products.split_at_checked(count as usize)?;
            products = rest;
            if from == s.fill {
                a.reg(Op::Xor, SUM, SUM);
            } else {
                values_need = values_need.max(from as usize + 1);
                a.mem(Op::Load, SUM, VALUES, from as usize);
            }
            for &(l, u) in now {
                let (l, u) = (l as usize, u as usize);
                (l_need, u_need) = (l_need.max(l + 1), u_need.max(u + 1));
                a.mem(Op::Load, PRODUCT, L, l);
                a.mem(Op::Mul, PRODUCT, U, u);
                a.reg(Op::Sub, SUM, PRODUCT);
            }
            let need = if target == U {
                &mut u_need
            } else {
                &mut l_need
            };
            *need = (*need).max(at + 1);
            a.store(SUM, target, at);
            Some(())
        };
        for j in 0..columns {
            let (us, ue) = (s.u_ptr[j], s.u_ptr[j + 1]);
            let (ls, le) = (s.l_ptr[j] + 1, s.l_ptr[j + 1]);
            if ue <= us || le < ls {
                return None;
            }
            for e in us..ue {
                entry(&mut a, U, e)?;
            }
            // The column's largest L entry before scaling, as the plan's
            // `if v.abs() > big { v.abs() } else { big }` (maxsd gives its
            // second operand when either is a NaN).
            a.reg(Op::Xor, BIG, BIG);
            for e in ls..le {
                entry(&mut a, L, e)?;
                a.reg(Op::Move, SCRATCH, SUM);
                a.reg(Op::And, SCRATCH, MASK_REG);
                a.reg(Op::Max, SCRATCH, BIG);
                a.reg(Op::Move, BIG, SCRATCH);
            }
            // Refused unless finite, not zero, and at least the threshold
            // times the largest entry below it (a NaN compares unordered,
            // which `jb` takes).
            a.mem(Op::Load, PIVOT, U, ue - 1);
            a.reg(Op::Move, PIVOT_ABS, PIVOT);
            a.reg(Op::And, PIVOT_ABS, MASK_REG);
            a.mem(Op::Mul, BIG, CONSTANTS, THRESHOLD);
            a.reg(Op::Compare, PIVOT_ABS, BIG);
            a.jump_to_label(Jump::Below);
            a.mem(Op::Compare, PIVOT_ABS, CONSTANTS, INFINITY);
            a.jump_to_label(Jump::AboveOrEqual);
            a.mem(Op::Compare, PIVOT_ABS, CONSTANTS, ZERO);
            a.jump_to_label(Jump::BelowOrEqual);
            // The reciprocal, and L's column times it.
            a.reg(Op::Move, SCRATCH, ONE_REG);
            a.reg(Op::Div, SCRATCH, PIVOT);
            a.store(SCRATCH, U_INV, j);
            for e in ls..le {
                a.mem(Op::Load, SUM, L, e);
                a.reg(Op::Mul, SUM, SCRATCH);
                a.store(SUM, L, e);
            }
        }
        a.return_value(1);
        a.label();
        a.return_value(0);
        // Every entry and product taken, once, and every instruction
        // written.
        if entries.next().is_some() || !products.is_empty() || a.failed() {
            return None;
        }
        Some(CompiledPlan {
            code: pages.seal()?,
            values_need,
            l_need,
            u_need,
            columns,
        })
    }

    /// The plan's refactorisation of `values` into `l`, `u` and `u_inv`, as
    /// [`super::refactor::Plan::run`] computes it: false at the first
    /// pivot refused (the entries of the later columns left as they were).
    ///
    /// Panics if an array is shorter than the code reads or writes.
    pub fn run(
        &self,
        values: &[f64],
        l: &mut [f64],
        u: &mut [f64],
        u_inv: &mut [f64],
        threshold: f64,
    ) -> bool {
        assert!(
            values.len() >= self.values_need
                && l.len() >= self.l_need
                && u.len() >= self.u_need
                && u_inv.len() >= self.columns,
            "arrays shorter than the compiled plan's"
        );
        let constants = [
            f64::from_bits(!(1u64 << 63)),
            1.0,
            threshold,
            f64::INFINITY,
            0.0,
        ];
        // SAFETY: the code (`new`) reads `values` below `values_need`, reads
        // and writes `l`, `u` and `u_inv` below `l_need`, `u_need` and
        // `columns`, and `constants` below its five, all checked above; it
        // touches no other memory, no register the System V convention
        // asks a function to keep (only rax and xmm0-7), nor the stack.
        unsafe {
            let f: unsafe extern "sysv64" fn(
                *const f64,
                *mut f64,
                *mut f64,
                *mut f64,
                *const f64,
            ) -> u32 = std::mem::transmute(self.code.entry());
            f(
                values.as_ptr(),
                l.as_mut_ptr(),
                u.as_mut_ptr(),
                u_inv.as_mut_ptr(),
                constants.as_ptr(),
            ) != 0
        }
    }
}
