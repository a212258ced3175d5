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
//! 1.3, and the 500-case path takes 8 % less (`docs/performance.md`). The
//! arithmetic is the plan's to the bit: the same products in the same
//! order, each rounded as Rust rounds `acc - l * u` (SSE2 scalar, no fused
//! product), the same pivot test and `1 / pivot`. The substitutions
//! likewise: a row's products in the loops' order, each `y[column] * value`
//! with constant displacements. Values just computed and read again soon
//! (a column's U entries, a substitution's rows) are read from registers
//! they were copied to, not from memory ([`Recent`]).
//!
//! Compiling costs what about a hundred runs save, and many structures (a
//! solve from the design, an identification's trial) are factorised only a
//! few times, so the loop runs a structure's first [`COMPILE_AFTER`] times
//! and the code the rest ([`Tiered`]).

use super::x86::{Asm, Base, Executable, Jump, Op, Writable, Xmm};
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU32, Ordering};

/// How many times a structure's work runs as a loop before it is compiled:
/// compiling the McPherson's plan costs 53-85 µs here (half of it fresh
/// pages), what 75-120 runs save (about 0.7 µs a run), so a structure that
/// has run this often and runs as often again repays it
/// (`docs/performance.md`).
pub(crate) const COMPILE_AFTER: u32 = 128;

/// Code compiled at the first use after [`COMPILE_AFTER`] uses, shared by
/// whoever shares the structure (on any thread).
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
    /// The code, compiling it by `compile` if [`COMPILE_AFTER`] uses came
    /// before this one; None before, or if it was not compiled (the caller
    /// runs the loop).
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
/// the pivot's reciprocal, the pivot, its absolute value (and an L entry's
/// before), and the two constants kept in registers.
const SUM: Xmm = Xmm::new(0);
const PRODUCT: Xmm = Xmm::new(1);
const BIG: Xmm = Xmm::new(2);
const INVERSE: Xmm = Xmm::new(3);
const PIVOT: Xmm = Xmm::new(4);
const PIVOT_ABS: Xmm = Xmm::new(5);
const ONE_REG: Xmm = Xmm::new(6);
const MASK_REG: Xmm = Xmm::new(7);

/// The values last written that are also kept in registers, in turn. A
/// value just computed is read again soon (a substitution's row by the
/// rows after it, an entry of U by the entries below it in its column):
/// from memory, each such read waits for the store before it, about seven
/// cycles on the chain of dependent rows, where a register copy waits
/// none. Reads are the same values either way (the same bits).
struct Recent {
    /// The registers used, in turn.
    regs: &'static [Xmm],
    /// The array and index of the value each register holds.
    held: [Option<(Base, usize)>; 16],
    /// The register the next value goes to.
    next: usize,
}

impl Recent {
    fn new(regs: &'static [Xmm]) -> Recent {
        Recent {
            regs,
            held: [None; 16],
            next: 0,
        }
    }

    /// The register holding `array[index]`, if one does.
    fn find(&self, array: Base, index: usize) -> Option<Xmm> {
        let s = self.held[..self.regs.len()]
            .iter()
            .position(|&h| h == Some((array, index)))?;
        Some(self.regs[s])
    }

    /// Keeps a copy of `array[index]` (now in `from`), in place of the
    /// oldest kept (and of an older copy of the same).
    fn keep(&mut self, a: &mut Asm, array: Base, index: usize, from: Xmm) {
        let n = self.regs.len();
        for h in &mut self.held[..n] {
            if *h == Some((array, index)) {
                *h = None;
            }
        }
        let s = self.next;
        self.next = (s + 1) % n;
        self.held[s] = Some((array, index));
        a.reg(Op::Move, self.regs[s], from);
    }

    /// `op dst, array[index]`, the operand from its register if one holds
    /// it (a load from a register is a move).
    fn operand(&self, a: &mut Asm, op: Op, dst: Xmm, array: Base, index: usize) {
        match self.find(array, index) {
            Some(r) => a.reg(if matches!(op, Op::Load) { Op::Move } else { op }, dst, r),
            None => a.mem(op, dst, array, index),
        }
    }
}

/// The registers a plan keeps its current column's last U entries in
/// (the others hold an entry's sum, a product, the pivot's test and the
/// constants).
const PLAN_KEEPS: [Xmm; 8] = registers::<8>(8);

/// The registers a substitution keeps its last rows in (all but the row's
/// sum and a product).
const SUBSTITUTION_KEEPS: [Xmm; 14] = registers::<14>(2);

// The kept registers are none of those the code computes in, nor more
// than `Recent` holds (checked when axle is compiled).
const _: () = {
    let plan_work = [
        SUM, PRODUCT, BIG, INVERSE, PIVOT, PIVOT_ABS, ONE_REG, MASK_REG,
    ];
    assert!(disjoint(&PLAN_KEEPS, &plan_work) && PLAN_KEEPS.len() <= 16);
    assert!(disjoint(&SUBSTITUTION_KEEPS, &[SUM, PRODUCT]) && SUBSTITUTION_KEEPS.len() <= 16);
};

/// Whether no register of `a` is in `b`.
const fn disjoint(a: &[Xmm], b: &[Xmm]) -> bool {
    let mut i = 0;
    while i < a.len() {
        let mut k = 0;
        while k < b.len() {
            if a[i].number() == b[k].number() {
                return false;
            }
            k += 1;
        }
        i += 1;
    }
    true
}

/// `N` registers from `xmm{first}` on.
const fn registers<const N: usize>(first: u8) -> [Xmm; N] {
    let mut r = [Xmm::new(0); N];
    let mut k = 0;
    while k < N {
        r[k] = Xmm::new(first + k as u8);
        k += 1;
    }
    r
}

/// The most products compiled (about 20 bytes of code each: 5 MiB). The
/// code outgrows the first-level cache already at the McPherson (46 kB for
/// its plan) and runs from the second: the gain falls with the size (11 %
/// of a warm thesis set at one corner, 7 % at eight coupled corners, even
/// on the car of 35 parts, `docs/performance.md`), but nowhere turns into
/// a loss.
pub(crate) const MAX_PRODUCTS: usize = 1 << 18;

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
        // a subtraction of 4), 21 an entry (its start and store of 8 each,
        // its register copy of 5) and 20 more an L entry (its largest, its
        // scaling), 96 a column (the pivot's test and reciprocal), and 16
        // for the last instruction's scratch ([`Asm`]), written straight
        // into the pages it will run from (each fresh page costs about
        // 2.5 µs here).
        let l_entries = s.l_ptr[columns]
            .checked_sub(s.l_ptr[0])?
            .checked_sub(columns)?;
        let bound =
            s.products.len() * 20 + s.entries.len() * 21 + l_entries * 20 + columns * 96 + 64;
        let mut pages = Writable::new(bound)?;
        let mut a = Asm::new(pages.bytes());
        a.mem(Op::Load, MASK_REG, CONSTANTS, ABS_MASK);
        a.mem(Op::Load, ONE_REG, CONSTANTS, ONE);
        let (mut values_need, mut l_need, mut u_need) = (0, 0, 0);
        let (mut entries, mut products) = (s.entries.iter(), s.products);
        // One entry of `target[at]`: its start, minus its products, in SUM
        // (the caller stores it).
        // The current column's U entries as they are computed: each is
        // read by the entries after it.
        let mut recent = Recent::new(&PLAN_KEEPS);
        let mut entry = |a: &mut Asm, recent: &Recent, target: Base, at: usize| -> Option<()> {
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
                recent.operand(a, Op::Mul, PRODUCT, U, u);
                a.reg(Op::Sub, SUM, PRODUCT);
            }
            let need = if target == U {
                &mut u_need
            } else {
                &mut l_need
            };
            *need = (*need).max(at + 1);
            Some(())
        };
        for j in 0..columns {
            let (us, ue) = (s.u_ptr[j], s.u_ptr[j + 1]);
            let (ls, le) = (s.l_ptr[j] + 1, s.l_ptr[j + 1]);
            if ue <= us || le < ls {
                return None;
            }
            for e in us..ue {
                entry(&mut a, &recent, U, e)?;
                a.store(SUM, U, e);
                recent.keep(&mut a, U, e, SUM);
            }
            // The pivot's reciprocal, then each entry of L times it as it is
            // computed (the plan's order: see `Plan::run_as_loop`).
            recent.operand(&mut a, Op::Load, PIVOT, U, ue - 1);
            a.reg(Op::Move, INVERSE, ONE_REG);
            a.reg(Op::Div, INVERSE, PIVOT);
            // The column's largest L entry before scaling, as the plan's
            // `if v.abs() > big { v.abs() } else { big }` (maxsd gives its
            // second operand when either is a NaN).
            a.reg(Op::Xor, BIG, BIG);
            for e in ls..le {
                entry(&mut a, &recent, L, e)?;
                a.reg(Op::Move, PIVOT_ABS, SUM);
                a.reg(Op::And, PIVOT_ABS, MASK_REG);
                a.reg(Op::Max, PIVOT_ABS, BIG);
                a.reg(Op::Move, BIG, PIVOT_ABS);
                a.reg(Op::Mul, SUM, INVERSE);
                a.store(SUM, L, e);
            }
            // Refused unless finite, not zero, and at least the threshold
            // times the largest entry below it (a NaN compares unordered,
            // which `jb` takes).
            a.reg(Op::Move, PIVOT_ABS, PIVOT);
            a.reg(Op::And, PIVOT_ABS, MASK_REG);
            a.mem(Op::Mul, BIG, CONSTANTS, THRESHOLD);
            a.reg(Op::Compare, PIVOT_ABS, BIG);
            a.jump_to_label(Jump::Below);
            a.mem(Op::Compare, PIVOT_ABS, CONSTANTS, INFINITY);
            a.jump_to_label(Jump::AboveOrEqual);
            a.mem(Op::Compare, PIVOT_ABS, CONSTANTS, ZERO);
            a.jump_to_label(Jump::BelowOrEqual);
            a.store(INVERSE, U_INV, j);
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
        // `columns`, and reads `constants` below its five, all checked
        // above; it touches no other memory, no register the System V
        // convention asks a function to keep (only rax and xmm registers),
        // nor the stack.
        let args = [
            values.as_ptr().cast_mut(),
            l.as_mut_ptr(),
            u.as_mut_ptr(),
            u_inv.as_mut_ptr(),
            constants.as_ptr().cast_mut(),
        ];
        unsafe { self.code.call(args) != 0 }
    }
}

/// The two substitutions of a solve ([`super::sparse::SparseLu::solve`])
/// as machine code: `L y' = y` row by row from the first, then `U z = y'`
/// from the last, each row's products in [`super::pivoting::Rows`]' order
/// (the loop's bits), and the arrays' least lengths.
#[derive(Debug)]
pub(crate) struct CompiledSubstitution {
    code: Executable,
    rows: usize,
    y_need: usize,
    l_need: usize,
    u_need: usize,
}

/// The generated substitution's arguments (System V): the vector solved in
/// place, L's and U's values, the pivots' reciprocals.
const Y: Base = Base::Rdi;
const L_VALUES: Base = Base::Rsi;
const U_VALUES: Base = Base::Rdx;
const INVERSES: Base = Base::Rcx;

impl CompiledSubstitution {
    /// The substitutions of `rows` (L's rows' entries `(column, index into
    /// l_val)` at `l[l_ptr[i]..l_ptr[i + 1]]`, U's likewise) as code; None
    /// if they have more than [`MAX_PRODUCTS`] products, a row's range is
    /// not in its entries, an index is too large, or the system gives no
    /// executable memory.
    pub fn new(
        l_ptr: &[usize],
        l: &[(u32, u32)],
        u_ptr: &[usize],
        u: &[(u32, u32)],
    ) -> Option<CompiledSubstitution> {
        if l.len() + u.len() > MAX_PRODUCTS || l_ptr.len() != u_ptr.len() {
            return None;
        }
        let rows = l_ptr.len().checked_sub(1)?;
        // 20 bytes a product, 29 a row (its load, store and scaling of 8,
        // its register copy of 5), and 16 for the last instruction's
        // scratch ([`Asm`]).
        let bound = (l.len() + u.len()) * 20 + 2 * rows * 29 + 64;
        let mut pages = Writable::new(bound)?;
        let mut a = Asm::new(pages.bytes());
        let (mut y_need, mut l_need, mut u_need) = (rows, 0, 0);
        // The rows last solved: each is read by the rows after it.
        let mut recent = Recent::new(&SUBSTITUTION_KEEPS);
        let mut row =
            |a: &mut Asm, recent: &Recent, i: usize, pairs: &[(u32, u32)], values: Base| {
                recent.operand(a, Op::Load, SUM, Y, i);
                for &(c, e) in pairs {
                    let (c, e) = (c as usize, e as usize);
                    y_need = y_need.max(c + 1);
                    let need = if values == L_VALUES {
                        &mut l_need
                    } else {
                        &mut u_need
                    };
                    *need = (*need).max(e + 1);
                    recent.operand(a, Op::Load, PRODUCT, Y, c);
                    a.mem(Op::Mul, PRODUCT, values, e);
                    a.reg(Op::Sub, SUM, PRODUCT);
                }
            };
        for i in 0..rows {
            let pairs = l.get(l_ptr[i]..l_ptr[i + 1])?;
            // (A row of L without entries leaves y's entry as it is.)
            if !pairs.is_empty() {
                row(&mut a, &recent, i, pairs, L_VALUES);
                a.store(SUM, Y, i);
                recent.keep(&mut a, Y, i, SUM);
            }
        }
        for i in (0..rows).rev() {
            row(&mut a, &recent, i, u.get(u_ptr[i]..u_ptr[i + 1])?, U_VALUES);
            a.mem(Op::Mul, SUM, INVERSES, i);
            a.store(SUM, Y, i);
            recent.keep(&mut a, Y, i, SUM);
        }
        a.return_value(0);
        if a.failed() {
            return None;
        }
        Some(CompiledSubstitution {
            code: pages.seal()?,
            rows,
            y_need,
            l_need,
            u_need,
        })
    }

    /// Solves `L U z = y` in place, as the loop does.
    ///
    /// Panics if an array is shorter than the code reads or writes.
    pub fn run(&self, y: &mut [f64], l_val: &[f64], u_val: &[f64], u_inv: &[f64]) {
        assert!(
            y.len() >= self.y_need
                && l_val.len() >= self.l_need
                && u_val.len() >= self.u_need
                && u_inv.len() >= self.rows,
            "arrays shorter than the compiled substitution's"
        );
        // SAFETY: the code (`new`) reads and writes `y` below `y_need` (its
        // rows and the columns it reads), reads `l_val`, `u_val` and `u_inv`
        // below `l_need`, `u_need` and `rows`, all checked above; it touches
        // no other memory, no register the System V convention asks a
        // function to keep (only rax and xmm registers), nor the stack.
        let args = [
            y.as_mut_ptr(),
            l_val.as_ptr().cast_mut(),
            u_val.as_ptr().cast_mut(),
            u_inv.as_ptr().cast_mut(),
            std::ptr::null_mut(),
        ];
        unsafe { self.code.call(args) };
    }
}

#[cfg(test)]
#[path = "compiled_tests.rs"]
mod tests;
