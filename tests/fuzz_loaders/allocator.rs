//! The counting allocator, the panic hook, and running a closure on a counted thread with a time limit.

use super::*;

pub(crate) struct CountingAllocator;

thread_local! {
    /// Whether this thread is running a case (only such threads are counted).
    static TRACKED: Cell<bool> = const { Cell::new(false) };
    static LIVE: Cell<isize> = const { Cell::new(0) };
    static PEAK: Cell<isize> = const { Cell::new(0) };
    /// The case being run, for the message of [`HARD_CAP`]: seed and index.
    static CASE_ID: Cell<(u64, u64)> = const { Cell::new((0, 0)) };
    /// The message of a panic on this thread during a case, caught or not.
    static PANIC_NOTE: RefCell<Option<String>> = const { RefCell::new(None) };
}

#[global_allocator]
pub(crate) static ALLOCATOR: CountingAllocator = CountingAllocator;

/// Counts `delta` bytes more (or fewer) live on this thread, if it is running a case; stops
/// the process where that passes [`HARD_CAP`].
pub(crate) fn count(delta: isize) {
    if !TRACKED.try_with(Cell::get).unwrap_or(false) {
        return;
    }
    let live = LIVE.try_with(|l| {
        l.set(l.get() + delta);
        l.get()
    });
    if let Ok(live) = live {
        let _ = PEAK.try_with(|p| p.set(p.get().max(live)));
        if live > HARD_CAP {
            hard_cap_exceeded(live);
        }
    }
}

/// Writes which case passed [`HARD_CAP`] without allocating, and aborts.
pub(crate) fn hard_cap_exceeded(live: isize) -> ! {
    let _ = TRACKED.try_with(|t| t.set(false));
    let (seed, index) = CASE_ID.try_with(Cell::get).unwrap_or((0, 0));
    let mut err = std::io::stderr();
    let mut digits = [0u8; 20];
    let _ = err.write_all(b"\nfuzz_loaders: a case would hold ");
    let _ = err.write_all(decimal(live as u64, &mut digits));
    let _ = err.write_all(b" bytes, past the hard cap; rerun it with MULTIRATE_FUZZ_SEED=");
    let _ = err.write_all(decimal(seed, &mut digits));
    let _ = err.write_all(b" MULTIRATE_FUZZ_CASE=");
    let _ = err.write_all(decimal(index, &mut digits));
    let _ = err.write_all(b"\n");
    std::process::abort();
}

/// `v` in decimal, in `buffer`, without allocating.
pub(crate) fn decimal(mut v: u64, buffer: &mut [u8; 20]) -> &[u8] {
    let mut start = buffer.len();
    loop {
        start -= 1;
        buffer[start] = b'0' + (v % 10) as u8;
        v /= 10;
        if v == 0 {
            return &buffer[start..];
        }
    }
}

unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count(layout.size() as isize);
        System.alloc(layout)
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count(layout.size() as isize);
        System.alloc_zeroed(layout)
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout);
        count(-(layout.size() as isize));
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count(new_size as isize - layout.size() as isize);
        System.realloc(ptr, layout, new_size)
    }
}

/// Every panic on a thread running a case is noted there (the loaders may catch their own);
/// others go to the usual hook.
pub(crate) fn install_panic_hook() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let usual = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if TRACKED.try_with(Cell::get).unwrap_or(false) {
                let note = format!("{info}");
                let _ = PANIC_NOTE.try_with(|n| {
                    let mut n = n.borrow_mut();
                    if n.is_none() {
                        *n = Some(note);
                    }
                });
            } else {
                usual(info);
            }
        }));
    });
}

/// What running a closure on a counted thread gave.
pub(crate) struct Tracked<T> {
    /// The closure's value, or the message of the panic that ended it.
    pub(crate) value: Result<T, String>,
    /// The first panic during the run, also one caught inside it.
    pub(crate) panic: Option<String>,
    /// Peak live bytes on the thread, over what it held when the closure started.
    pub(crate) peak: usize,
    pub(crate) elapsed: Duration,
}

/// Runs `f` on a fresh thread with the allocator counting, as case `id`. `Err` if it has not
/// returned after [`HANG_LIMIT`] (the thread is left behind).
pub(crate) fn run_tracked<T: Send + 'static>(
    id: (u64, u64),
    f: impl FnOnce() -> T + Send + 'static,
) -> Result<Tracked<T>, Duration> {
    install_panic_hook();
    let (send, receive) = mpsc::channel();
    std::thread::Builder::new()
        .name(format!("fuzz-case-{}", id.1))
        .spawn(move || {
            CASE_ID.with(|c| c.set(id));
            PANIC_NOTE.with(|n| n.borrow_mut().take());
            LIVE.with(|l| l.set(0));
            PEAK.with(|p| p.set(0));
            let start = Instant::now();
            TRACKED.with(|t| t.set(true));
            let value = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
            TRACKED.with(|t| t.set(false));
            let elapsed = start.elapsed();
            let peak = PEAK.with(Cell::get).max(0) as usize;
            let panic = PANIC_NOTE.with(|n| n.borrow_mut().take());
            let value = value.map_err(|payload| {
                payload
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_else(|| "a panic without a message".into())
            });
            let _ = send.send(Tracked { value, panic, peak, elapsed });
        })
        .expect("spawn a case thread");
    receive.recv_timeout(HANG_LIMIT).map_err(|_| HANG_LIMIT)
}
