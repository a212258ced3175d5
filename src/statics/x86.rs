//! The few x86-64 instructions the compiled refactorisation and
//! substitutions are made of ([`super::compiled`]), encoded, and the
//! executable memory they run from.
//!
//! Only scalar SSE2 on doubles (the baseline x86-64 that axle is built for,
//! so the arithmetic is the compiled Rust's to the bit: one rounding a
//! multiplication, one a subtraction, no fused product), on registers
//! `xmm0`-`xmm15` (all free for a function to use in the System V
//! convention), with memory operands `[base + 8 i]` on the first five
//! integer argument registers. The encodings are checked against GNU as's
//! in the tests below.

use std::ptr::NonNull;

/// A base register of a memory operand: the System V argument registers,
/// in argument order (the generated function's pointers).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Base {
    Rdi,
    Rsi,
    Rdx,
    Rcx,
    R8,
}

impl Base {
    /// The register's number in ModRM's `rm` field, and whether it needs
    /// REX.B (r8).
    fn rm(self) -> (u8, bool) {
        match self {
            Base::Rdi => (7, false),
            Base::Rsi => (6, false),
            Base::Rdx => (2, false),
            Base::Rcx => (1, false),
            Base::R8 => (0, true),
        }
    }
}

/// An SSE register, `xmm0` to `xmm15` (the upper eight through a REX
/// prefix; a larger number would spill into the ModRM byte's other fields,
/// so none can be made).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Xmm(u8);

impl Xmm {
    /// `xmm{n}`; panics unless `n < 16` (at compile time in a constant).
    pub const fn new(n: u8) -> Xmm {
        assert!(n < 16, "only xmm0 to xmm15");
        Xmm(n)
    }

    /// The register's number.
    pub const fn number(self) -> u8 {
        self.0
    }

    /// The register's low three bits (ModRM's field) and its fourth (REX's
    /// R or B bit).
    fn low_and_high(self) -> (u8, u8) {
        (self.0 & 7, self.0 >> 3)
    }
}

/// A REX prefix with the given R and B bits, or none if both are clear
/// (W and X are never needed here).
fn rex(r: u8, b: u8) -> Option<u8> {
    (r | b != 0).then_some(0x40 | r << 2 | b)
}

/// An instruction's start written at the start of `bytes`: its prefix, its
/// REX byte if it has one, 0F and the opcode; how many bytes that took.
fn opcode(bytes: &mut [u8; 16], prefix: u8, rex: Option<u8>, code: u8) -> usize {
    let mut n = 0;
    for b in [Some(prefix), rex, Some(0x0F), Some(code)]
        .into_iter()
        .flatten()
    {
        bytes[n] = b;
        n += 1;
    }
    n
}

/// Scalar double operations `op xmm, xmm/m64` (prefix F2) and the packed
/// ones used on a register's low lane (prefix 66).
#[derive(Debug, Clone, Copy)]
pub(crate) enum Op {
    /// `movsd xmm, m64` (F2 0F 10); as a store, see [`Asm::store`].
    Load,
    Mul,
    Sub,
    Div,
    /// `maxsd a, b`: `a > b ? a : b`, and `b` when either is a NaN.
    Max,
    /// `ucomisd a, b`: the flags of an unordered comparison.
    Compare,
    /// `xorpd` (a register with itself: +0).
    Xor,
    /// `andpd` (with the sign bit's mask: the absolute value).
    And,
    /// `movapd` between registers.
    Move,
}

impl Op {
    fn code(self) -> (u8, u8) {
        match self {
            Op::Load => (0xF2, 0x10),
            Op::Mul => (0xF2, 0x59),
            Op::Sub => (0xF2, 0x5C),
            Op::Div => (0xF2, 0x5E),
            Op::Max => (0xF2, 0x5F),
            Op::Compare => (0x66, 0x2E),
            Op::Xor => (0x66, 0x57),
            Op::And => (0x66, 0x54),
            Op::Move => (0x66, 0x28),
        }
    }
}

/// A condition of a jump after [`Op::Compare`] (`ucomisd a, b`; unordered
/// sets the carry).
#[derive(Debug, Clone, Copy)]
pub(crate) enum Jump {
    /// `jb`: `a < b`, or unordered.
    Below,
    /// `jae`: `a >= b`, ordered.
    AboveOrEqual,
    /// `jbe`: `a <= b`, or unordered.
    BelowOrEqual,
}

/// Machine code written into a buffer of a fixed size, with forward jumps
/// to one exit label. An instruction that does not fit (the buffer full, a
/// displacement past 32 bits) is not written, and the code is marked
/// failed ([`Self::failed`]). Each instruction is written as 16 bytes, its
/// own and whatever follows in a scratch array, the next written over the
/// rest: a copy of a fixed size is two moves, one of the instruction's
/// length a call to `memcpy` (the emission took 7 ns an instruction).
#[derive(Debug)]
pub(crate) struct Asm<'a> {
    buf: &'a mut [u8],
    len: usize,
    failed: bool,
    /// Where each jump to the label keeps its 32-bit displacement.
    to_label: Vec<usize>,
}

impl<'a> Asm<'a> {
    pub fn new(buf: &'a mut [u8]) -> Asm<'a> {
        Asm {
            buf,
            len: 0,
            failed: false,
            to_label: Vec::new(),
        }
    }

    /// The code written.
    #[cfg(test)]
    pub fn code(&self) -> &[u8] {
        &self.buf[..self.len]
    }

    /// Whether an instruction could not be written.
    pub fn failed(&self) -> bool {
        self.failed
    }

    /// The first `n` of `bytes` (`n <= 16`), if 16 bytes are left.
    #[inline]
    fn put16(&mut self, bytes: [u8; 16], n: usize) {
        match self.buf.get_mut(self.len..self.len + 16) {
            Some(at) if !self.failed => {
                at.copy_from_slice(&bytes);
                self.len += n;
            }
            _ => self.failed = true,
        }
    }

    #[inline]
    fn put<const N: usize>(&mut self, bytes: [u8; N]) {
        let mut all = [0u8; 16];
        all[..N].copy_from_slice(&bytes);
        self.put16(all, N);
    }

    /// `op xmm, xmm`.
    pub fn reg(&mut self, op: Op, dst: Xmm, src: Xmm) {
        let (prefix, code) = op.code();
        let ((d, r), (s, b)) = (dst.low_and_high(), src.low_and_high());
        let mut bytes = [0u8; 16];
        let n = opcode(&mut bytes, prefix, rex(r, b), code);
        bytes[n] = 0xC0 | d << 3 | s;
        self.put16(bytes, n + 1);
    }

    /// `op xmm, [base + 8 index]`.
    pub fn mem(&mut self, op: Op, dst: Xmm, base: Base, index: usize) {
        let (prefix, code) = op.code();
        self.memory_operand(prefix, code, dst, base, index);
    }

    /// `movsd [base + 8 index], xmm`.
    pub fn store(&mut self, src: Xmm, base: Base, index: usize) {
        self.memory_operand(0xF2, 0x11, src, base, index);
    }

    fn memory_operand(&mut self, prefix: u8, code: u8, reg: Xmm, base: Base, index: usize) {
        let Some(disp) = index.checked_mul(8).and_then(|d| i32::try_from(d).ok()) else {
            self.failed = true;
            return;
        };
        let (rm, rex_b) = base.rm();
        let (r, rex_r) = reg.low_and_high();
        let modrm = |mode: u8| mode << 6 | r << 3 | rm;
        // Prefix, REX (R for xmm8-15, B for r8), opcode, ModRM,
        // displacement (none, 8 or 32 bits; no base here is rbp or r13,
        // whose mode 0 means another operand).
        let mut bytes = [0u8; 16];
        let n = opcode(&mut bytes, prefix, rex(rex_r, u8::from(rex_b)), code);
        let (mode, width) = match disp {
            0 => (0, 0),
            -128..=127 => (1, 1),
            _ => (2, 4),
        };
        bytes[n] = modrm(mode);
        bytes[n + 1..n + 5].copy_from_slice(&disp.to_le_bytes());
        self.put16(bytes, n + 1 + width);
    }

    /// A jump to the label when `cond` holds.
    pub fn jump_to_label(&mut self, cond: Jump) {
        let code = match cond {
            Jump::Below => 0x82,
            Jump::AboveOrEqual => 0x83,
            Jump::BelowOrEqual => 0x86,
        };
        self.put([0x0F, code, 0, 0, 0, 0]);
        if !self.failed {
            self.to_label.push(self.len - 4);
        }
    }

    /// `mov eax, value; ret`.
    pub fn return_value(&mut self, value: u32) {
        if value == 0 {
            self.put([0x31, 0xC0, 0xC3]);
        } else {
            let [v0, v1, v2, v3] = value.to_le_bytes();
            self.put([0xB8, v0, v1, v2, v3, 0xC3]);
        }
    }

    /// Places the label here: the jumps written so far land on the next
    /// instruction.
    pub fn label(&mut self) {
        let here = self.len;
        for at in self.to_label.drain(..) {
            match i32::try_from(here - (at + 4)) {
                Ok(rel) => self.buf[at..at + 4].copy_from_slice(&rel.to_le_bytes()),
                Err(_) => self.failed = true,
            }
        }
    }
}

/// Pages mapped for writing code into, then sealed into an [`Executable`].
#[derive(Debug)]
pub(crate) struct Writable(Executable);

/// Machine code in memory mapped for reading and running, not writing
/// (written while it was mapped for writing only), and unmapped when
/// dropped.
#[derive(Debug)]
pub(crate) struct Executable {
    at: NonNull<u8>,
    len: usize,
}

// SAFETY: the mapping is read-only once made, and owned by this value.
unsafe impl Send for Executable {}
// SAFETY: as above: nothing writes it.
unsafe impl Sync for Executable {}

/// Pages given at once, not one fault at a time as the code is written (a
/// fault costs about 2 µs on the hosts measured).
#[cfg(target_os = "linux")]
const POPULATE: libc::c_int = libc::MAP_POPULATE;
#[cfg(not(target_os = "linux"))]
const POPULATE: libc::c_int = 0;

impl Writable {
    /// At least `len` bytes of fresh pages, mapped for reading and writing;
    /// None if the system refuses.
    pub fn new(len: usize) -> Option<Writable> {
        // SAFETY: sysconf has no preconditions.
        let page = usize::try_from(unsafe { libc::sysconf(libc::_SC_PAGESIZE) })
            .ok()
            .filter(|&p| p > 0)?;
        let len = len.max(1).div_ceil(page).checked_mul(page)?;
        // SAFETY: an anonymous private mapping at an address of the
        // system's choice; the result is checked.
        let at = unsafe {
            libc::mmap(
                std::ptr::null_mut(),
                len,
                libc::PROT_READ | libc::PROT_WRITE,
                libc::MAP_PRIVATE | libc::MAP_ANONYMOUS | POPULATE,
                -1,
                0,
            )
        };
        if at == libc::MAP_FAILED {
            return None;
        }
        Some(Writable(Executable {
            at: NonNull::new(at.cast::<u8>())?,
            len,
        }))
    }

    pub fn bytes(&mut self) -> &mut [u8] {
        // SAFETY: the mapping is `len` bytes, readable and writable (zero
        // when fresh), and only this value refers to it.
        unsafe { std::slice::from_raw_parts_mut(self.0.at.as_ptr(), self.0.len) }
    }

    /// The pages made read and execute only; None if the system refuses
    /// (a hardened kernel may forbid executable pages made at run time: the
    /// caller then does without). x86 keeps the instruction cache coherent
    /// with the stores.
    pub fn seal(self) -> Option<Executable> {
        let Writable(mapped) = self;
        // SAFETY: the mapping made in `new`, whole.
        let sealed = unsafe {
            libc::mprotect(
                mapped.at.as_ptr().cast(),
                mapped.len,
                libc::PROT_READ | libc::PROT_EXEC,
            )
        };
        // (Refused: dropped, so unmapped.)
        (sealed == 0).then_some(mapped)
    }
}

impl Executable {
    /// Calls the code as `extern "sysv64" fn(five pointers) -> u32` (the
    /// one shape of every function generated here: unused arguments are
    /// passed null) and returns its result.
    ///
    /// # Safety
    /// The code is such a function, and every memory access it makes
    /// through the pointers is within the arrays they point into (reads
    /// only where the caller holds no more than a shared borrow); it
    /// keeps the registers and stack the convention asks a function to
    /// keep.
    pub unsafe fn call(&self, args: [*mut f64; 5]) -> u32 {
        type Generated =
            unsafe extern "sysv64" fn(*mut f64, *mut f64, *mut f64, *mut f64, *mut f64) -> u32;
        // SAFETY: the caller's (the code is a function of this type).
        unsafe {
            let f: Generated = std::mem::transmute(self.at.as_ptr());
            f(args[0], args[1], args[2], args[3], args[4])
        }
    }
}

impl Drop for Executable {
    fn drop(&mut self) {
        // SAFETY: the mapping made in `Writable::new`, unmapped once.
        unsafe {
            libc::munmap(self.at.as_ptr().cast(), self.len);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every instruction form the compiled refactorisation uses, against
    /// the bytes GNU as 2.40 assembled from the same instructions in Intel
    /// syntax (in the comments; the jumps written `{disp32} jb fail` and so
    /// on, to the `xor` after the first `ret`).
    #[test]
    fn the_encodings_are_the_assemblers() {
        let mut buf = [0u8; 256];
        let mut a = Asm::new(&mut buf);
        let [x0, x1, x2, x3, x4, x5, x6, x7] = [0, 1, 2, 3, 4, 5, 6, 7].map(Xmm::new);
        a.mem(Op::Load, x0, Base::Rdi, 2); // movsd xmm0, [rdi+0x10]
        a.mem(Op::Load, x1, Base::Rsi, 128); // movsd xmm1, [rsi+0x400]
        a.mem(Op::Mul, x1, Base::Rdx, 1); // mulsd xmm1, [rdx+0x8]
        a.mem(Op::Mul, x1, Base::Rdx, 15); // mulsd xmm1, [rdx+0x78]
        a.mem(Op::Mul, x1, Base::Rdx, 16); // mulsd xmm1, [rdx+0x80]
        a.reg(Op::Sub, x0, x1); // subsd xmm0, xmm1
        a.store(x0, Base::Rdx, 64); // movsd [rdx+0x200], xmm0
        a.store(x4, Base::Rcx, 0); // movsd [rcx], xmm4
        a.reg(Op::Xor, x0, x0); // xorpd xmm0, xmm0
        a.reg(Op::Move, x3, x0); // movapd xmm3, xmm0
        a.reg(Op::And, x3, x7); // andpd xmm3, xmm7
        a.reg(Op::Max, x3, x2); // maxsd xmm3, xmm2
        a.mem(Op::Load, x7, Base::R8, 0); // movsd xmm7, [r8]
        a.mem(Op::Load, x6, Base::R8, 1); // movsd xmm6, [r8+0x8]
        a.mem(Op::Mul, x3, Base::R8, 2); // mulsd xmm3, [r8+0x10]
        a.reg(Op::Compare, x5, x3); // ucomisd xmm5, xmm3
        a.mem(Op::Compare, x5, Base::R8, 3); // ucomisd xmm5, [r8+0x18]
        a.mem(Op::Div, x4, Base::Rdx, 512); // divsd xmm4, [rdx+0x1000]
        a.reg(Op::Mul, x5, x4); // mulsd xmm5, xmm4
        a.jump_to_label(Jump::Below); // jb fail
        a.jump_to_label(Jump::AboveOrEqual); // jae fail
        a.jump_to_label(Jump::BelowOrEqual); // jbe fail
        a.return_value(1); // mov eax, 1; ret
        a.label(); // fail:
        a.return_value(0); // xor eax, eax; ret
        let gnu_as = "f20f104710f20f108e00040000f20f594a08f20f594a78f20f598a80000000\
                      f20f5cc1f20f118200020000f20f1121660f57c0660f28d8660f54df\
                      f20f5fdaf2410f1038f2410f107008f2410f595810660f2eeb\
                      66410f2e6818f20f5ea200100000f20f59ec0f82120000000f830c000000\
                      0f8606000000b801000000c331c0c3";
        assert_assembled(&a, gnu_as);
    }

    /// The code written, in full and as GNU as's bytes (in hex).
    fn assert_assembled(a: &Asm, gnu_as: &str) {
        assert!(!a.failed());
        let hex: String = a.code().iter().map(|b| format!("{b:02x}")).collect();
        assert_eq!(hex, gnu_as);
    }

    /// The upper eight registers through REX.R and REX.B, alone and with
    /// r8 as the base.
    #[test]
    fn the_upper_registers_are_the_assemblers() {
        let mut buf = [0u8; 128];
        let mut a = Asm::new(&mut buf);
        let x = |n| Xmm::new(n);
        a.reg(Op::Move, x(9), x(0)); // movapd xmm9, xmm0
        a.reg(Op::Mul, x(1), x(12)); // mulsd xmm1, xmm12
        a.mem(Op::Load, x(10), Base::Rsi, 128); // movsd xmm10, [rsi+0x400]
        a.store(x(15), Base::Rdx, 1); // movsd [rdx+0x8], xmm15
        a.mem(Op::Mul, x(11), Base::R8, 2); // mulsd xmm11, [r8+0x10]
        a.reg(Op::Sub, x(13), x(14)); // subsd xmm13, xmm14
        a.reg(Op::Move, x(0), x(8)); // movapd xmm0, xmm8
        a.mem(Op::Load, x(8), Base::Rdi, 0); // movsd xmm8, [rdi]
        let gnu_as = "66440f28c8f2410f59ccf2440f109600040000f2440f117a08\
                      f2450f595810f2450f5cee66410f28c0f2440f1007";
        assert_assembled(&a, gnu_as);
    }

    /// A displacement past 32 bits fails the code, and so does a full
    /// buffer; nothing is written after.
    #[test]
    fn a_displacement_past_32_bits_or_a_full_buffer_fails() {
        let mut buf = [0u8; 64];
        let mut a = Asm::new(&mut buf);
        a.mem(Op::Load, Xmm::new(0), Base::Rdi, (1 << 28) - 1);
        assert!(!a.failed() && a.code().len() == 8);
        a.mem(Op::Load, Xmm::new(0), Base::Rdi, 1 << 28);
        assert!(a.failed());
        a.reg(Op::Sub, Xmm::new(0), Xmm::new(1));
        assert_eq!(a.code().len(), 8);
        let mut small = [0u8; 7];
        let mut b = Asm::new(&mut small);
        b.mem(Op::Load, Xmm::new(0), Base::Rdi, 16);
        assert!(b.failed() && b.code().is_empty());
        let mut c = Asm::new(&mut buf);
        c.store(Xmm::new(0), Base::Rdi, usize::MAX);
        assert!(c.failed());
    }

    /// A register past xmm15 cannot be made (its number would spill into
    /// the ModRM byte's mode).
    #[test]
    #[should_panic(expected = "only xmm0 to xmm15")]
    fn only_sixteen_registers() {
        let n = std::hint::black_box(16);
        Xmm::new(n);
    }

    /// Code made executable runs: a function returning 1, then one
    /// returning 0.
    #[test]
    fn code_made_executable_runs() {
        for value in [1, 0] {
            let mut pages = Writable::new(16).expect("writable memory");
            let mut a = Asm::new(pages.bytes());
            a.return_value(value);
            assert!(!a.failed());
            let code = pages.seal().expect("executable memory");
            // SAFETY: the code is `mov eax, value; ret` (or `xor`): it
            // touches no memory and no register but eax.
            let got = unsafe { code.call([std::ptr::null_mut(); 5]) };
            assert_eq!(got, value);
        }
    }
}
