# lmfilm — the main job and the checks. `make help` lists the targets.
CARGO ?= cargo
SCENE ?= scenes/examples/cours_tree3.lm
TIME ?= 4

.PHONY: film test check lint bench bench-render help

help:
	@echo "make film   derive the default scene and ray-trace it to renders/film.png (SCENE=…, TIME=…)"
	@echo "make test   build and run the whole test suite"
	@echo "make lint   cargo fmt --check and cargo clippy --all-targets"
	@echo "make bench  criterion benchmarks of the step function and the turtle"
	@echo "make bench-render  the forest against Embree and Mitsuba 3 (../shared/anchors)"

film:
	$(CARGO) run --release -- still $(SCENE) --time $(TIME) -o renders/film.png
	@echo "wrote renders/film.png"

test:
	$(CARGO) test --all-targets

lint:
	$(CARGO) fmt --check
	$(CARGO) clippy --all-targets -- -D warnings

check: lint test

bench:
	$(CARGO) bench --bench step
	$(CARGO) bench --bench scene

bench-render:
	sh scripts/bench_render.sh
