/* rjt_impl_hooked.c - the library's implementation with its allocation hooks routed to
   the linking test's rjt_malloc and rjt_free (tests/rjt_alloc.h), compiled once per
   flavour for the tests that watch the library's memory. */
#include "rjt_alloc.h"
#define RJ_MALLOC(sz, ctx) rjt_malloc((sz), (ctx))
#define RJ_FREE(p, ctx) rjt_free((p), (ctx))
#define REVJOINT_IMPLEMENTATION
#include "../revjoint.h"
