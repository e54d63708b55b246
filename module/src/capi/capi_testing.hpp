// Test hook of the C interface: makes the next guarded entry point throw inside, so that tests
// can check that no exception crosses aerial.h and which status each exception becomes. Not part
// of the public interface.
#pragma once

namespace aerial::capi {

enum class InjectedException {
    none,
    bad_alloc,           ///< std::bad_alloc: AERIAL_ERROR_OUT_OF_MEMORY
    standard_exception,  ///< std::runtime_error: AERIAL_ERROR_INTERNAL
    unknown,             ///< a thrown int: AERIAL_ERROR_INTERNAL
};

/// Arms the hook for the next guarded call on this thread (it disarms itself when it fires).
void inject_exception_in_next_call(InjectedException kind);

}  // namespace aerial::capi
