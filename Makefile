# quadcast -- the two entry points of the quick start. Each does all of the set-up on a fresh
# Debian 12 machine: installs the missing Debian packages, configures, builds, runs.
BUILD ?= build
JOBS ?= $(shell nproc)
DEB_PACKAGES := cmake g++ clang make pkg-config libeigen3-dev libglm-dev glslang-tools glslang-dev \
  doctest-dev libosmesa6-dev libcli11-dev nlohmann-json3-dev libtbb-dev libmpfrc++-dev libmpfr-dev \
  libgmp-dev libbenchmark-dev libpng-dev nlohmann-json3-dev pymol-data zlib1g-dev
DEMO_PACKAGES :=

.PHONY: all deps demo-deps configure build test demo regenerate clean data install

all: build

deps:
	@missing=$$(for p in $(DEB_PACKAGES); do dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q '^install ok installed' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages:" $$missing; \
	  SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq --no-install-recommends $$missing; \
	fi

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

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

DEMO_SCENES := 1tii_balls_and_sticks 1tii_space_filling il2_balls_and_sticks il2_space_filling quads_cube primitives marschner_lobb_qss reflective \
  skull_s31 liver_qss bunny_sdf_s31

demo: build demo-deps data
	@mkdir -p demo-out
	$(BUILD)/tools/quadcast verify
	$(BUILD)/tools/quadcast bench stability
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
