# revjoint.h - build, tests, demo, benchmarks. The library itself is revjoint.h alone,
# generated from its parts in src/ (tools/amalgamate.sh; make rebuilds it).
#   make          examples and tools into build/
#   make demo     the deployment benchmark: CSV history, frames and a plot into out/
#   make test     every test; ends with one line "N passed, M failed"
#   make golden   regenerate tests/golden (commit with a message that says why they moved)
#   make bench    speed against error -> BENCHMARKS.md
#   make stress   the numerical-stability suite
# System packages (libosmesa6-dev libpng-dev pkg-config clang g++) are installed by
# tools/deps.sh when missing and we are root; otherwise it prints the apt-get line.

CC      ?= gcc
OPT     ?= -O2
# -std=c99 and -ffp-contract=off: no FMA contraction, so gcc -O0/-O2/-O3 and clang give
# bit-identical histories (measured; see README) and the golden files hold across them.
WARN    = -std=c99 -Wall -Wextra -pedantic -Werror -ffp-contract=off
CFLAGS  ?= $(OPT)
ALLCF   = $(WARN) $(CFLAGS) -I.
B       = build
# the renderer's programs: OSMesa's headers, libpng; OSMesa itself is not linked but opened
# on first use (dlopen in render/rj_render.c), so a program that draws nothing never loads
# it (nor LLVM). glibc 2.34+ has dlopen and pthread_once in libc: -ldl -lpthread are empty
# there and add nothing, and are needed before.
GL      = $(shell pkg-config --cflags osmesa libpng 2>/dev/null) $(shell pkg-config --libs libpng 2>/dev/null) -lm -ldl -lpthread
SAN     = -O1 -g -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer

HDR     = revjoint.h
RENDER  = render/rj_render.c render/rj_render.h
EXAMPLES = $(B)/impact $(B)/deploy $(B)/animate $(B)/pngdiff $(B)/quickstart $(B)/studies $(B)/rj $(B)/segmented $(B)/a02 $(B)/pd_arm \
          $(B)/peer_side $(B)/rigid_cross $(B)/pin_forces
TESTS   = $(B)/test_core $(B)/test_beam $(B)/test_dynamics $(B)/test_benchmarks $(B)/test_rigid2 \
          $(B)/test_render $(B)/csvdiff $(B)/test_core_asan $(B)/test_dynamics_asan $(B)/test_beam_asan \
          $(B)/test_core_clang $(B)/test_cpp $(B)/test_state $(B)/test_state_asan $(B)/test_scene $(B)/test_scene_asan $(B)/test_mixed $(B)/test_mixed_asan $(B)/test_loads $(B)/test_loads_asan $(B)/test_deploy_damped $(B)/test_deploy_damped_asan $(B)/test_applied $(B)/test_applied_asan $(B)/test_robust $(B)/test_robust_asan $(B)/test_drive $(B)/test_drive_asan $(B)/test_couple $(B)/test_couple_asan $(B)/test_rows $(B)/test_rows_asan $(B)/test_loops $(B)/test_loops_asan $(B)/stress

.PHONY: all deps test demo golden bench stress clean check-header valgrind fuzz peer
all: deps $(EXAMPLES)

deps:
	@sh tools/deps.sh

$(B):
	@mkdir -p $(B)

# The header is generated: src/*.h joined in the order of src/parts.txt. Edit src/.
$(HDR): $(wildcard src/*.h) src/parts.txt tools/amalgamate.sh
	@sh tools/amalgamate.sh

# The examples are single files, each defining REVJOINT_IMPLEMENTATION as a user's would.
# Built here they link the implementation compiled once ($(B)/rj_impl.o; EXCF sets the
# header's latch that skips it in their own file): the same code, compiled once.
EXCF    = $(ALLCF) -DREVJOINT_IMPLEMENTATION_DONE
$(B)/impact: examples/impact.c examples/scenes.h examples/cli.h $(HDR) $(RENDER) $(B)/rj_render.o $(B)/rj_impl.o | $(B)
	$(CC) $(EXCF) examples/impact.c $(B)/rj_render.o $(B)/rj_impl.o -o $@ $(GL)
$(B)/deploy: examples/deploy.c examples/scenes.h examples/cli.h examples/rigid2.h $(HDR) $(RENDER) $(B)/rj_render.o $(B)/rj_impl.o | $(B)
	$(CC) $(EXCF) examples/deploy.c $(B)/rj_render.o $(B)/rj_impl.o -o $@ $(GL)
$(B)/animate: examples/animate.c examples/scenes.h examples/cli.h $(HDR) $(RENDER) $(B)/rj_render.o $(B)/rj_impl.o | $(B)
	$(CC) $(EXCF) examples/animate.c $(B)/rj_render.o $(B)/rj_impl.o -o $@ $(GL)
$(B)/rj: examples/rj.c examples/scenes.h examples/cli.h $(HDR) $(RENDER) $(B)/rj_render.o $(B)/rj_impl.o | $(B)
	$(CC) $(EXCF) examples/rj.c $(B)/rj_render.o $(B)/rj_impl.o -o $@ $(GL)
$(B)/studies: examples/studies.c examples/scenes.h examples/rigid2.h examples/cli.h $(HDR) $(B)/rj_impl.o | $(B)
	$(CC) $(EXCF) $< $(B)/rj_impl.o -o $@ -lm
$(B)/quickstart: examples/quickstart.c $(HDR) | $(B)
	$(CC) $(ALLCF) $< -o $@ -lm
$(B)/pngdiff: render/pngdiff.c $(RENDER) | $(B)
	$(CC) $(ALLCF) -DRJR_PNG_ONLY render/pngdiff.c render/rj_render.c -o $@ $(shell pkg-config --cflags --libs libpng 2>/dev/null) -lm

# The implementation compiled once per flavour (tests/rjt_impl.c); the test programs that
# use the public API alone include the header plain and link it, as a program of several
# files would; the two that watch the library's memory link it compiled with their
# allocation hooks (tests/rjt_impl_hooked.c). test_mixed reads private internals and
# compiles it itself.
TDEPS   = tests/rjt.h tests/rjt_loads.h examples/scenes.h examples/rigid2.h $(HDR)
LINKED  = $(B)/test_core $(B)/test_beam $(B)/test_benchmarks $(B)/test_loads $(B)/test_deploy_damped $(B)/test_applied $(B)/test_drive $(B)/test_couple $(B)/test_rows $(B)/test_loops \
          $(B)/test_robust $(B)/test_dynamics
LINKED_ASAN = $(B)/test_core_asan $(B)/test_beam_asan $(B)/test_loads_asan $(B)/test_deploy_damped_asan $(B)/test_applied_asan $(B)/test_drive_asan $(B)/test_couple_asan $(B)/test_rows_asan $(B)/test_loops_asan \
          $(B)/test_robust_asan $(B)/test_dynamics_asan
$(B)/rj_impl_hooked.o: tests/rjt_impl_hooked.c tests/rjt_alloc.h $(HDR) | $(B)
	$(CC) $(ALLCF) -c $< -o $@
$(B)/rj_impl_hooked_asan.o: tests/rjt_impl_hooked.c tests/rjt_alloc.h $(HDR) | $(B)
	$(CC) $(WARN) $(SAN) -I. -c $< -o $@
$(B)/test_state: tests/test_state.c tests/rjt_alloc.h $(TDEPS) $(B)/rj_impl_hooked.o | $(B)
	$(CC) $(ALLCF) $< $(B)/rj_impl_hooked.o -o $@ -lm
$(B)/test_state_asan: tests/test_state.c tests/rjt_alloc.h $(TDEPS) $(B)/rj_impl_hooked_asan.o | $(B)
	$(CC) $(WARN) $(SAN) -I. $< $(B)/rj_impl_hooked_asan.o -o $@ -lm
$(B)/rj_impl.o: tests/rjt_impl.c $(HDR) | $(B)
	$(CC) $(ALLCF) -c $< -o $@
$(B)/rj_impl_asan.o: tests/rjt_impl.c $(HDR) | $(B)
	$(CC) $(WARN) $(SAN) -I. -c $< -o $@
$(B)/rj_impl_clang.o: tests/rjt_impl.c $(HDR) | $(B)
	clang $(WARN) -O2 -I. -c $< -o $@
$(B)/rj_impl_cpp.o: tests/rjt_impl.c $(HDR) | $(B)
	g++ -x c++ -std=c++11 -Wall -Wextra -pedantic -Werror -O2 -I. -c $< -o $@
# the renderer compiled once for the tests
$(B)/rj_render.o: render/rj_render.c render/rj_render.h | $(B)
	$(CC) $(ALLCF) $(shell pkg-config --cflags osmesa libpng 2>/dev/null) -c $< -o $@

$(LINKED): $(B)/test_%: tests/test_%.c $(TDEPS) $(B)/rj_impl.o | $(B)
	$(CC) $(ALLCF) $< $(B)/rj_impl.o -o $@ -lm
$(LINKED_ASAN): $(B)/test_%_asan: tests/test_%.c $(TDEPS) $(B)/rj_impl_asan.o | $(B)
	$(CC) $(WARN) $(SAN) -I. $< $(B)/rj_impl_asan.o -o $@ -lm
$(B)/test_%: tests/test_%.c $(TDEPS) | $(B)
	$(CC) $(ALLCF) $< -o $@ -lm
$(B)/test_render: tests/test_render.c tests/rjt.h examples/scenes.h $(HDR) $(B)/rj_impl.o $(B)/rj_render.o | $(B)
	$(CC) $(ALLCF) tests/test_render.c $(B)/rj_render.o $(B)/rj_impl.o -o $@ $(GL)
$(B)/test_%_asan: tests/test_%.c $(TDEPS) | $(B)
	$(CC) $(WARN) $(SAN) -I. $< -o $@ -lm
$(B)/test_core_clang: tests/test_core.c tests/rjt.h examples/scenes.h $(HDR) $(B)/rj_impl_clang.o | $(B)
	clang $(WARN) -O2 -I. tests/test_core.c $(B)/rj_impl_clang.o -o $@ -lm
$(B)/test_cpp: tests/test_core.c tests/rjt.h examples/scenes.h $(HDR) $(B)/rj_impl_cpp.o | $(B)
	g++ -x c++ -std=c++11 -Wall -Wextra -pedantic -Werror -O2 -I. tests/test_core.c -x none $(B)/rj_impl_cpp.o -o $@ -lm
# test code formats long diagnostics into fixed buffers: truncation there is harmless
$(B)/test_scene: tests/test_scene.c tests/rjt_alloc.h $(TDEPS) $(B)/rj_impl_hooked.o | $(B)
	$(CC) $(ALLCF) -Wno-format-truncation $< $(B)/rj_impl_hooked.o -o $@ -lm
$(B)/test_scene_asan: tests/test_scene.c tests/rjt_alloc.h $(TDEPS) $(B)/rj_impl_hooked_asan.o | $(B)
	$(CC) $(WARN) -Wno-format-truncation $(SAN) -I. $< $(B)/rj_impl_hooked_asan.o -o $@ -lm
$(B)/stress: tests/stress.c tests/rjt.h examples/scenes.h $(HDR) $(B)/rj_impl.o | $(B)
	$(CC) $(ALLCF) -Wno-format-truncation $< $(B)/rj_impl.o -o $@ -lm
$(B)/bench: bench/bench.c examples/scenes.h examples/rigid2.h $(HDR) $(RENDER) $(B)/rj_render.o | $(B)
	$(CC) $(ALLCF) bench/bench.c $(B)/rj_render.o -o $@ $(GL)
$(B)/a02: bench/a02.c $(HDR) | $(B)
	$(CC) $(ALLCF) $< -o $@ -lm
# where the rigid solvers cross (dense Cholesky, articulated bodies); reads internals
$(B)/rigid_cross: bench/rigid_cross.c $(HDR) | $(B)
	$(CC) $(ALLCF) $< -o $@ -lm
# every joint's pin force at once on chains of inextensible links (public API alone)
$(B)/pin_forces: bench/pin_forces.c $(HDR) | $(B)
	$(CC) $(ALLCF) $< -o $@ -lm
$(B)/segmented: bench/segmented.c examples/scenes.h $(HDR) | $(B)
	$(CC) $(ALLCF) $< -o $@ -lm
$(B)/pd_arm: examples/pd_arm.c examples/scenes.h examples/cli.h $(HDR) $(B)/rj_impl.o | $(B)
	$(CC) $(EXCF) $< $(B)/rj_impl.o -o $@ -lm
# revjoint.h side by side with the MuJoCo peer; it runs build/peer_mujoco as a program, so
# it builds without MuJoCo
$(B)/peer_side: bench/peer_side.c examples/scenes.h examples/cli.h $(HDR) $(RENDER) $(B)/rj_render.o | $(B)
	$(CC) $(ALLCF) bench/peer_side.c $(B)/rj_render.o -o $@ $(GL)
# the MuJoCo peer of the deployment (docs/validation.md); needs libmujoco-dev, which
# nothing else here does
peer: | $(B)
	@test -f /usr/include/mujoco/mujoco.h || { echo "make peer: needs libmujoco-dev (apt-get install libmujoco-dev)"; exit 1; }
	$(CC) $(ALLCF) -isystem /usr/include bench/peer_mujoco.c -o $(B)/peer_mujoco -lmujoco -lm
$(B)/csvdiff: tests/csvdiff.c | $(B)
	$(CC) $(ALLCF) $< -o $@ -lm

# The header alone: warning-free with gcc and clang as C99, and as C++; no mutable globals.
check-header: | $(B)
	@printf '#define REVJOINT_IMPLEMENTATION\n#include "revjoint.h"\n' > $(B)/impl.c
	@for cc in gcc clang; do \
	  if $$cc -std=c99 -Wall -Wextra -pedantic -Werror -I. -c $(B)/impl.c -o $(B)/impl_$$cc.o 2>$(B)/impl_$$cc.log; \
	  then echo "PASS header builds warning-free: $$cc -std=c99 -Wall -Wextra -pedantic -Werror"; \
	  else echo "FAIL header warnings with $$cc:"; cat $(B)/impl_$$cc.log; fi; done
	@if g++ -x c++ -Wall -Wextra -pedantic -Werror -I. -c $(B)/impl.c -o $(B)/impl_cpp.o 2>$(B)/impl_cpp.log; \
	  then echo "PASS header compiles as C++ (g++ -Wall -Wextra -pedantic -Werror)"; else echo "FAIL header as C++:"; cat $(B)/impl_cpp.log; fi
	@g=$$(nm $(B)/impl_gcc.o | awk '$$2 ~ /^[BbDdCGS]$$/ {print $$3}'); \
	  if [ -z "$$g" ]; then echo "PASS no mutable globals in the implementation (nm)"; else echo "FAIL mutable globals: $$g"; fi

GOLDEN_IMPACT = $(foreach m,penalty adaptive momentum forced energy,$(foreach r,rc12 rc13,$(m)_$(r)))

# make test builds on every processor by itself, after deps (which may install the
# packages the build needs), then runs the tests as many at once (tests/run.sh)
NPROC  := $(shell nproc 2>/dev/null || echo 1)
test: deps | $(B)
	@sh tools/amalgamate.sh --check > $(B)/amalgamate.txt 2>&1 || true
	@$(MAKE) -s -j$(NPROC) $(EXAMPLES) $(TESTS)
	@sh tests/run.sh "cat $(B)/amalgamate.txt" "$(MAKE) -s check-header" \
	  "$(B)/test_core" "$(B)/test_core_clang" "$(B)/test_cpp" "$(B)/test_beam" "$(B)/test_dynamics" \
	  "$(B)/test_benchmarks" "$(B)/test_rigid2" "$(B)/test_state" \
	  "$(B)/test_core_asan" "$(B)/test_beam_asan" "$(B)/test_dynamics_asan" "$(B)/test_state_asan" \
	  "$(B)/test_scene" "$(B)/test_scene_asan" "$(B)/test_mixed" "$(B)/test_mixed_asan" "$(B)/test_loads" "$(B)/test_loads_asan" "$(B)/test_deploy_damped" "$(B)/test_deploy_damped_asan" "$(B)/test_applied" "$(B)/test_applied_asan" "$(B)/test_drive" "$(B)/test_drive_asan" "$(B)/test_couple" "$(B)/test_couple_asan" "$(B)/test_rows" "$(B)/test_rows_asan" "$(B)/test_loops" "$(B)/test_loops_asan" \
	  "$(B)/test_robust" "$(B)/test_robust_asan" \
	  "/usr/bin/python3 tests/elastica_ref.py" "/usr/bin/python3 tests/keys.py" \
	  "$(B)/stress --short" \
	  "sh tests/readme.sh $(B)" \
	  "sh tests/golden.sh $(B)" \
	  "sh tests/lanes.sh $(B)" \
	  "$(B)/test_render" \
	  "sh tests/cli.sh $(B)" \
	  "sh tests/rj.sh $(B)" \
	  "sh tests/tutorial.sh $(B)" \
	  "sh tests/sweep.sh $(B)"

golden: deps $(EXAMPLES) $(B)/test_render
	@sh tests/golden.sh $(B) --write
	@$(B)/test_render --write-golden

demo: deps $(B)/deploy
	@mkdir -p out
	$(B)/deploy --csv out/deploy.csv --plot out/deploy_angles.png --frames out/frames
	$(B)/deploy --rigid --csv out/deploy_rigid.csv
	@echo "demo: wrote out/deploy.csv (flexible history), out/deploy_rigid.csv (rigid reference),"
	@echo "      out/deploy_angles.png (plot), out/frames/frame_*.png (animation)"
	@echo "      video: ffmpeg -framerate 30 -i out/frames/frame_%05d.png -pix_fmt yuv420p out/deploy.mp4"

# valgrind memcheck over the unit tests (errors or leaks fail; see README)
valgrind: deps $(B)/test_core $(B)/test_beam $(B)/test_dynamics $(B)/test_state
	@sh tests/run.sh "valgrind --error-exitcode=9 --leak-check=full --errors-for-leak-kinds=definite,indirect -q $(B)/test_core" \
	  "valgrind --error-exitcode=9 --leak-check=full --errors-for-leak-kinds=definite,indirect -q $(B)/test_beam" \
	  "valgrind --error-exitcode=9 --leak-check=full --errors-for-leak-kinds=definite,indirect -q $(B)/test_state" \
	  "valgrind --error-exitcode=9 --leak-check=full --errors-for-leak-kinds=definite,indirect -q $(B)/test_dynamics"

# The numerical-stability suite: every limit method on the hard cases; the table
# goes to out/stress.md. --short is the quick version.
stress: deps $(B)/stress
	@mkdir -p out
	@sh tests/run.sh "$(B)/stress --table out/stress.md"

# Speed against error: BENCHMARKS.md and the work-precision plots (about 7 minutes); with
# MuJoCo installed (libmujoco-dev) also section 7, revjoint.h side by side with the peer
# (build/peer_side, about 1.5 minutes more)
NATIVE_CF = -std=c99 -O3 -march=native -Wall -Wextra -pedantic -Werror -ffp-contract=off
$(B)/bench_native: bench/bench.c examples/scenes.h examples/rigid2.h $(HDR) $(RENDER) | $(B)
	$(CC) $(NATIVE_CF) -I. -DBENCH_CFLAGS='"$(NATIVE_CF)"' bench/bench.c render/rj_render.c -o $@ $(GL)
bench: deps $(B)/bench $(B)/bench_native $(B)/peer_side
	@mkdir -p docs out
	$(B)/bench_native --only throughput --out out/bench_native.md
	@rm -f out/peer.md
	@if [ -f /usr/include/mujoco/mujoco.h ]; then \
	  $(MAKE) peer && $(B)/peer_side --out out/peer.md --plot docs/peer_work_precision.png; \
	else echo "make bench: no MuJoCo (libmujoco-dev), so no side-by-side section"; fi
	$(B)/bench --out BENCHMARKS.md --plot docs/work_precision.png --native out/bench_native.md \
	  $$(test -f out/peer.md && echo --peer out/peer.md)

# Fuzzing with clang's libFuzzer, ASan and UBSan (undefined behaviour stops the run), one
# process per target: the scene-file parser, checkpoint loading (rj_state_load) and model
# building from definition structs (rj_model_create). `make fuzz` runs the three in turn,
# FUZZ_SECONDS each (600 by default), each even when one before it found a crash;
# `make fuzz-scene`, `fuzz-state`, `fuzz-model` run one.
# Crashes are written to the current directory as crash-* (libFuzzer's default).
FUZZ_SECONDS ?= 600
FUZZ_CF = -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all -Wall -Wextra -I.
.PHONY: fuzz-scene fuzz-state fuzz-model
$(B)/fuzz_%: tests/fuzz_%.c $(HDR) | $(B)
	clang $(FUZZ_CF) $< -o $@ -lm
$(B)/fuzz_state: tests/fuzz_state.c examples/scenes.h $(HDR) | $(B)
	clang $(FUZZ_CF) $< -o $@ -lm
fuzz: deps
	$(MAKE) -k fuzz-scene fuzz-state fuzz-model
fuzz-scene: $(B)/fuzz_scene
	@mkdir -p $(B)/fuzz_work
	$(B)/fuzz_scene -jobs=1 -max_total_time=$(FUZZ_SECONDS) -max_len=8192 -timeout=10 $(B)/fuzz_work tests/fuzz_corpus
# seeds: a valid checkpoint of each of the target's models, raw and with small edits
# (rewritten by: clang -DFUZZ_STATE_CORPUS tests/fuzz_state.c -I. -o build/fuzz_state_corpus -lm
# && build/fuzz_state_corpus tests/fuzz_corpus_state, after a change to the models or the format)
fuzz-state: $(B)/fuzz_state
	@mkdir -p $(B)/fuzz_work_state
	$(B)/fuzz_state -jobs=1 -max_total_time=$(FUZZ_SECONDS) -max_len=4096 -timeout=10 $(B)/fuzz_work_state tests/fuzz_corpus_state
fuzz-model: $(B)/fuzz_model
	@mkdir -p $(B)/fuzz_work_model
	$(B)/fuzz_model -jobs=1 -max_total_time=$(FUZZ_SECONDS) -max_len=1024 -timeout=10 $(B)/fuzz_work_model

clean:
	rm -rf $(B) out
