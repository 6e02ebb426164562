# quadcast -- the two entry points of the quick start. Each does all of the set-up on a fresh
# Debian 12 machine: installs the missing Debian packages, configures, builds, runs.
BUILD ?= build
JOBS ?= $(shell nproc)
# The ParaView plugin (paraview/) and its pvbatch tests on 1 and 2 MPI ranks under Xvfb: ParaView
# 5.11's development files, pvbatch and its Python, MPI, and the development packages ParaView's
# CMake package looks for (Debian's paraview-dev does not depend on them).
PARAVIEW_PACKAGES := paraview paraview-dev python3-paraview python3-numpy python3-dev openmpi-bin libopenmpi-dev \
  libhdf5-openmpi-dev libutfcpp-dev libglew-dev liblz4-dev libdouble-conversion-dev libtiff-dev xvfb xauth
DEB_PACKAGES := cmake g++ clang make pkg-config libeigen3-dev libglm-dev glslang-tools glslang-dev \
  doctest-dev libosmesa6-dev libcli11-dev nlohmann-json3-dev libtbb-dev libmpfrc++-dev libmpfr-dev \
  libgmp-dev libbenchmark-dev libpng-dev nlohmann-json3-dev pymol-data zlib1g-dev libclang-rt-14-dev \
  libcgal-dev libgmsh-dev $(PARAVIEW_PACKAGES)
DEMO_PACKAGES :=
# `make bench-vtk` only: VTK 9 (the peer renderer), NumPy for its arrays, Xvfb for its display.
BENCH_VTK_PACKAGES := python3-vtk9 python3-numpy xvfb xauth

.PHONY: bench-vtk bench-paraview all deps demo-deps configure build test demo regenerate clean data install fuzz fuzz-build test-sanitize test-clang

all: build

deps:
	@missing=$$(for p in $(DEB_PACKAGES); do dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q '^install ok installed' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages:" $$missing; \
	  SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq --no-install-recommends $$missing; \
	fi

bench-vtk-deps:
	@missing=$$(for p in $(BENCH_VTK_PACKAGES); do dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q '^install ok installed' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq --no-install-recommends $$missing; \
	fi

# quadcast against VTK's impostor mappers on the scenes of `bench spheres` / `bench sticks`, in one
# run (tools/bench_vtk.py; BENCH_VTK_ARGS e.g. "--cases spheres:1000000 --rounds 7").
BENCH_VTK_ARGS ?=
bench-vtk: build bench-vtk-deps
	/usr/bin/python3 tools/bench_vtk.py --quadcast $(BUILD)/tools/quadcast $(BENCH_VTK_ARGS)

# The ParaView plugin's Quadric Glyphs against ParaView's Point Gaussian and 3D Glyphs
# representations in pvbatch (paraview/bench/glyphs_bench.py), on 1 and on 2 MPI ranks, per count;
# then its Spline Isosurface against the Contour filter (paraview/bench/isosurface_bench.py) per
# Wavelet size.
BENCH_PARAVIEW_COUNTS ?= 10000 100000 1000000
BENCH_PARAVIEW_FRAMES ?= 5
BENCH_PARAVIEW_ISO_SIZES ?= 128
bench-paraview: build
	@for n in $(BENCH_PARAVIEW_COUNTS); do for r in 1 2; do \
	  /usr/bin/python3 tools/with_xvfb.py -- mpirun --allow-run-as-root --oversubscribe -np $$r pvbatch \
	    paraview/bench/glyphs_bench.py $(BUILD)/lib/quadcast/paraview/Quadcast/Quadcast.so --count $$n --frames $(BENCH_PARAVIEW_FRAMES) || exit 1; \
	done; done
	@for n in $(BENCH_PARAVIEW_ISO_SIZES); do for r in 1 2; do \
	  /usr/bin/python3 tools/with_xvfb.py -- mpirun --allow-run-as-root --oversubscribe -np $$r pvbatch \
	    paraview/bench/isosurface_bench.py $(BUILD)/lib/quadcast/paraview/Quadcast/Quadcast.so --size $$n --frames $(BENCH_PARAVIEW_FRAMES) || exit 1; \
	done; done

demo-deps:
	@missing=$$(for p in $(DEMO_PACKAGES); do dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q '^install ok installed' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq --no-install-recommends $$missing; \
	fi

configure: deps
	@[ -f $(BUILD)/CMakeCache.txt ] || cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo

build: configure
	cmake --build $(BUILD) -j $(JOBS)

# CGAL's sample data first (`data`): the tests on it (tests/slim: the kitten, bunny, fandisk and
# dragon; tests/gl: the GL SLIM bunny) skip themselves, saying so, where it could not be fetched.
test: build fuzz-build
	@tools/fetch_cgal_data.sh $(DATA_DIR) || echo "make test: CGAL's sample data could not be fetched; the tests on it will be skipped"
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# libFuzzer harnesses of every reader (tests/fuzz), built with Clang, ASan and UBSan in their own
# directory: only the harnesses and the reader libraries. `make test` builds them (when Clang has
# libFuzzer) so that ctest's fuzz_short_* runs them for a few seconds each; `make fuzz` runs
# each for FUZZ_SECONDS, keeping what it finds in $(FUZZ_BUILD)/corpus/<reader>.
FUZZ_BUILD ?= build-fuzz
FUZZ_SECONDS ?= 600
FUZZ_READERS := scene_json pdb off inr inr_gz nrrd raw slim msh
FUZZ_FLAGS := -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -fsanitize=fuzzer-no-link
fuzz-build: deps
	@if echo 'extern "C" int LLVMFuzzerTestOneInput(const char*, unsigned long) { return 0; }' | \
	    clang++ -x c++ -fsanitize=fuzzer -o /dev/null - 2>/dev/null; then \
	  [ -f $(FUZZ_BUILD)/CMakeCache.txt ] || cmake -S . -B $(FUZZ_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	    -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_FLAGS="$(FUZZ_FLAGS)" -DQUADCAST_PARAVIEW_PLUGIN=OFF \
	    -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" || exit 1; \
	  cmake --build $(FUZZ_BUILD) -j $(JOBS) --target $(addprefix fuzz_,$(FUZZ_READERS)) || exit 1; \
	else echo "fuzz-build: clang++ has no libFuzzer (apt-get install clang libclang-rt-14-dev); fuzz tests are skipped"; fi

fuzz: fuzz-build
	@for r in $(FUZZ_READERS); do \
	  echo "== fuzz_$$r for $(FUZZ_SECONDS) s"; \
	  tests/fuzz/run_fuzzer.sh $(FUZZ_BUILD)/tests/fuzz/fuzz_$$r tests/fuzz/corpus/$$r $(FUZZ_SECONDS) $(FUZZ_BUILD)/corpus/$$r || exit 1; \
	done

# The input tests under AddressSanitizer + UndefinedBehaviorSanitizer (GCC, its own build
# directory): the scene and volume test programs and the fuzz harnesses replaying their
# corpora. Left out by default: the OpenGL tests (gl, render, verify_kernels: llvmpipe under ASan
# is slow and reports leaks inside Mesa), the CLI tests (they need the whole CLI with the GL
# harness built under ASan: add them with SANITIZE_TARGETS="... quadcast_cli" and a wider
# SANITIZE_TESTS, e.g. '^(scene|volume|fuzz_replay_.*|cli_render_.*|cli_volume_info_.*)$$'),
# the package and codegen-comparison tests that build the project again, and the benches.
SANITIZE_BUILD ?= build-sanitize
SANITIZE_TARGETS ?= test_scene test_volume $(addprefix fuzz_,$(FUZZ_READERS))
SANITIZE_TESTS ?= ^(scene|volume|fuzz_replay_.*)$$
test-sanitize: deps
	@[ -f $(SANITIZE_BUILD)/CMakeCache.txt ] || cmake -S . -B $(SANITIZE_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DQUADCAST_PARAVIEW_PLUGIN=OFF \
	  -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
	  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined"
	cmake --build $(SANITIZE_BUILD) -j $(JOBS) --target $(SANITIZE_TARGETS)
	cd $(SANITIZE_BUILD) && ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=print_stacktrace=1 \
	  ctest --output-on-failure -j $(JOBS) -R '$(SANITIZE_TESTS)'

# The whole project built with Debian's Clang in its own build directory and every test run
# (the portability check beside the GCC build of `make test`; not part of it, since it doubles
# the build time).
CLANG_BUILD ?= build-clang
test-clang: deps
	@[ -f $(CLANG_BUILD)/CMakeCache.txt ] || CC=clang CXX=clang++ cmake -S . -B $(CLANG_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo
	cmake --build $(CLANG_BUILD) -j $(JOBS)
	cd $(CLANG_BUILD) && ctest --output-on-failure -j $(JOBS)

DEMO_SCENES := 1tii_balls_and_sticks 1tii_space_filling il2_balls_and_sticks il2_space_filling quads_cube primitives marschner_lobb_qss reflective \
  skull_s31 liver_qss bunny_sdf_s31 slim_bunny slim_kitten slim_fandisk slim_dragon tetmesh_tangle 1tii_skin il2_skin

demo: build demo-deps data
	@mkdir -p demo-out
	$(BUILD)/tools/quadcast verify
	$(BUILD)/tools/quadcast bench stability
	$(BUILD)/tools/quadcast slim-build $(DATA_DIR)/ChineseDragon-10kv.off -o $(DATA_DIR)/dragon_2e-3.slim --error 2e-3 --samples 100000
	$(BUILD)/tools/quadcast-msh-example -o $(DATA_DIR)/tangle_order2.msh --field tangle --box -3,3 --size 0.3 --order 2 --binary
	@for s in $(DEMO_SCENES); do \
	  $(BUILD)/tools/quadcast render examples/demo/$$s.json -o demo-out/$$s.png --width 1024 --height 768 --frames 3 || exit 1; \
	done
	$(BUILD)/tools/quadcast bench isosurfaces --volume $(DATA_DIR)/skull_2.9.inr --frames 3 --cpu-frames 1
	@echo "PNGs in demo-out/"

# CGAL's sample volumes and meshes (skull_2.9.inr, liver.inr.gz, armadillo.off, bunny00.off) from
# the Debian package libcgal-demo, downloaded once into $(DATA_DIR) (the demo scenes refer to
# build/data/).
DATA_DIR ?= build/data
data:
	tools/fetch_cgal_data.sh $(DATA_DIR)

# Installs the headers, the component libraries, the CMake package and the programs into PREFIX.
PREFIX ?= /usr/local
install: build
	cmake --install $(BUILD) --prefix $(PREFIX)

regenerate: build
	$(BUILD)/codegen/quadcast-codegen --out generated

clean:
	rm -rf $(BUILD)
