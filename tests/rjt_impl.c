/* rjt_impl.c - the library's implementation, compiled once per flavour (plain, sanitizers,
   clang, C++) for the test programs that use its public API alone: they include the
   header plain and link this, as a program of several files would. */
#define REVJOINT_IMPLEMENTATION
#include "../revjoint.h"
