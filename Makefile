# lmfilm — the main job and the checks. `make help` lists the targets.
CARGO ?= cargo

.PHONY: film check-video test test-worlds check lint bench bench-render bench-path bench-denoise bench-film bench-farm readable clean help

help:
	@echo "make film   the built-in film (14 s of the tennis match on its set): frames, soundtrack, manifest and the video renders/lmfilm/lmfilm.mp4"
	@echo "make check-video  the built-in film's MP4 played in headless Chromium (apt-get install chromium)"
	@echo "make test   build and run the whole test suite"
	@echo "make test-worlds  actors on hundreds of generated worlds (LMFILM_WORLDS=N per family, default 50): the table of docs/actors.md"
	@echo "make lint   cargo fmt --check and cargo clippy --all-targets"
	@echo "make bench  criterion benchmarks of the step function and the turtle"
	@echo "make bench-render  the forest against Embree and Mitsuba 3 (../shared/anchors)"
	@echo "make bench-path  the path tracer against Mitsuba 3's path integrator: agreement, equal samples, equal error"
	@echo "make bench-denoise  the denoiser against Open Image Denoise, and Mitsuba in equal time (W=320 for docs/performance.md)"
	@echo "make bench-film  the film pipeline: the built-in film at 1 and 2 threads, serial fraction, CPU busy, stage breakdown, a 1080p frame per sample against the forest still"
	@echo "make bench-farm  the Slurm chain on the two-node test cluster (scripts/slurm_up.sh), healthy and with one node broken"
	@echo "make readable  spell every scene in the readable form again (scenes/**/*.lmr, after a scene's .lm changed)"
	@echo "make clean  remove build products and renders (but renders/README.md)"

film:
	$(CARGO) run --release -- run

# The built-in film's video played in headless Chromium (Debian's
# `chromium`): size, duration, sound, played to the end.
check-video: film
	python3 scripts/play_in_browser.py renders/lmfilm

test:
	$(CARGO) test --all-targets

test-worlds:
	$(CARGO) test --test actors hundreds_of_generated_worlds -- --ignored --nocapture

lint:
	$(CARGO) fmt --check
	$(CARGO) clippy --all-targets -- -D warnings

check: lint test

bench:
	$(CARGO) bench --bench step
	$(CARGO) bench --bench scene
	$(CARGO) bench --bench sound
	$(CARGO) bench --bench physics

bench-render:
	sh scripts/bench_render.sh

bench-path:
	sh scripts/bench_path.sh

bench-denoise:
	sh scripts/bench_denoise.sh

bench-film:
	sh scripts/bench_film.sh

bench-farm:
	bash scripts/bench_farm.sh

readable:
	$(CARGO) build --release
	for f in $$(find scenes -name '*.lm' | sort); do ./target/release/lmfilm convert "$$f" -o "$${f%.lm}.lmr" || exit 1; done

clean:
	$(CARGO) clean
	find renders -mindepth 1 ! -name README.md -exec rm -rf {} +
