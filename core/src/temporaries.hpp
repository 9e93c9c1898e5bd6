#pragma once
// Shared by atomic_file.cpp and interrupt.cpp: the temporaries of the AtomicFiles in flight, removed by
// the handler of remove_temporary_files_on_signal() and by the signal thread of take_stop_signals().

namespace spinmotor::detail {

/// Unlinks the temporary file of every AtomicFile in flight (async-signal-safe: unlink(2) only).
void remove_temporaries_in_flight() noexcept;

}  // namespace spinmotor::detail
