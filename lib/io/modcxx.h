/*
 * modcxx.h - what every module's C++ side does alike (the modules alone
 * include it).
 */
#ifndef VDT_MODCXX_H
#define VDT_MODCXX_H

#ifndef __cplusplus
#error "modcxx.h is for the modules' C++ files"
#endif

#include <exception>

/*
 * For a module's ABI check, the first call after loading: the C++
 * runtime's per-thread exception state, which a C program that loads it
 * keeps in dynamic thread-local storage, is made now. Made at the first
 * throw (out of memory, say) or at exit, its allocation failing ended the
 * process ("cannot allocate memory for thread-local data", status 127)
 * past every catch.
 */
static inline void
vdt_cxx_thread_ready()
{
	volatile int made = std::uncaught_exceptions(); /* (pure: kept only if used) */
	(void)made;
}

#endif
