/* rjt_alloc.h - the allocation hooks of tests/rjt_impl_hooked.c: the implementation
   compiled with RJ_MALLOC and RJ_FREE routed to these, which the test that links it
   defines (test_scene counts live blocks and fails the n-th allocation; test_state counts
   allocations to prove the step makes none). */
#ifndef RJT_ALLOC_H
#define RJT_ALLOC_H
#include <stddef.h>
void *rjt_malloc(size_t size, void *ctx);
void rjt_free(void *p, void *ctx);
#endif
