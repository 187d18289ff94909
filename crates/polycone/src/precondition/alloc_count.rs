//! A counting global allocator for this crate's unit tests (per thread, so that tests running
//! in parallel do not see each other's allocations).

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use super::*;

thread_local! {
    static COUNT: Cell<usize> = const { Cell::new(0) };
}

fn bump() {
    let _ = COUNT.try_with(|c| c.set(c.get() + 1));
}

struct Counting;

// SAFETY: every call is forwarded to the system allocator unchanged.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        bump();
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        bump();
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        bump();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations (including reallocations) made by this thread while running `f`.
pub(crate) fn allocations_in<F: FnOnce()>(f: F) -> usize {
    let before = COUNT.with(Cell::get);
    f();
    COUNT.with(Cell::get) - before
}

pub(super) fn golden_for_tests(case: &str) -> DMatrix<f64> {
    let path = format!(
        "{}/../../testdata/cones/{case}.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(path).unwrap();
    let j: serde_json::Value = serde_json::from_str(&text).unwrap();
    let rows: Vec<Vec<f64>> = serde_json::from_value(j["generators"]["float64"].clone()).unwrap();
    DMatrix::from_fn(rows.len(), 6, |i, k| rows[i][k])
}

/// A warm `whiten_into` allocates nothing (full rank, rank-deficient with equations,
/// scaled, and the zero cone). Prints the allocations of a warm `span_to_face` (39 before
/// this whitening, 10 with it, on the single support).
#[test]
fn warm_whitening_does_not_allocate() {
    let tol = Tolerances::default();
    let single = golden_for_tests("single_support_flat");
    let mut flat = single.clone();
    flat.column_mut(2).fill(0.0);
    let inputs = [
        single.clone(),
        golden_for_tests("double_support_flat"),
        flat,
        &single * 1e200,
        DMatrix::zeros(3, 6),
    ];
    let (mut out, mut scratch) = (Whitened::default(), WhitenScratch::default());
    for v in &inputs {
        whiten_into(v, &tol, &mut out, &mut scratch);
    }
    for v in &inputs {
        let n = allocations_in(|| whiten_into(v, &tol, &mut out, &mut scratch));
        assert_eq!(n, 0, "{} x {} input", v.nrows(), v.ncols());
    }
    let opts = crate::DdOptions::default();
    let mut ws = crate::Workspace::new();
    for _ in 0..3 {
        ws.span_to_face(&single, &opts).unwrap();
    }
    let n = allocations_in(|| {
        std::hint::black_box(ws.span_to_face(&single, &opts).unwrap());
    });
    eprintln!("warm span_to_face, single support: {n} allocations");
}
