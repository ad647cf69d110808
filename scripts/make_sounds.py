#!/usr/bin/env python3
"""Generate the sound library of appendix D (tables D.1 and D.2) of Noser's
thesis as small WAV files in scenes/sounds/.

Output format: mono, 16-bit PCM, 22,050 Hz, peak-normalised to -3 dBFS.

* Synthesised sounds (ball hits, cricket, frog, forest, start beep, Vivaldi,
  airplane, silence) use only the Python standard library with fixed seeds,
  so running the script twice gives byte-identical files.
* Spoken words are produced with espeak-ng (English voice), trimmed of
  leading/trailing silence, faded and normalised.  espeak-ng is only needed
  to regenerate them; its output may differ between espeak-ng versions.

Usage:
    python3 scripts/make_sounds.py [--out DIR] [--no-speech] [--only NAME ...]

The generated files are committed; a build never runs this script.
"""

import argparse
import math
import os
import random
import shutil
import struct
import subprocess
import sys
import tempfile
import wave

SR = 22050
PEAK = 10.0 ** (-3.0 / 20.0)  # -3 dBFS
TWO_PI = 2.0 * math.pi


# --------------------------------------------------------------------------
# small DSP toolkit (pure Python, deterministic)
# --------------------------------------------------------------------------

def n_of(t):
    return int(round(t * SR))


def zeros(n):
    return [0.0] * n


def add_into(dst, src, at=0, gain=1.0, wrap=False):
    """Mix src into dst starting at sample `at` (circularly if wrap)."""
    n = len(dst)
    for i, v in enumerate(src):
        j = at + i
        if wrap:
            j %= n
        elif j >= n:
            break
        if j >= 0:
            dst[j] += gain * v


def white(rng, n):
    return [rng.random() * 2.0 - 1.0 for _ in range(n)]


def lowpass1(x, fc, circular=False):
    """One-pole low-pass.  circular=True filters the buffer as one period of
    a loop (two passes, keep the second) so the result loops seamlessly."""
    a = math.exp(-TWO_PI * fc / SR)
    b = 1.0 - a
    y = 0.0
    if circular:
        for v in x:
            y = b * v + a * y
    out = [0.0] * len(x)
    for i, v in enumerate(x):
        y = b * v + a * y
        out[i] = y
    return out


def highpass1(x, fc, circular=False):
    lp = lowpass1(x, fc, circular)
    return [v - l for v, l in zip(x, lp)]


def biquad(x, kind, f0, q, circular=False):
    """RBJ cookbook biquad: kind 'lp', 'hp' or 'bp' (0 dB peak)."""
    w0 = TWO_PI * f0 / SR
    cw, sw = math.cos(w0), math.sin(w0)
    alpha = sw / (2.0 * q)
    if kind == "lp":
        b0, b1, b2 = (1 - cw) / 2, 1 - cw, (1 - cw) / 2
    elif kind == "hp":
        b0, b1, b2 = (1 + cw) / 2, -(1 + cw), (1 + cw) / 2
    elif kind == "bp":
        b0, b1, b2 = alpha, 0.0, -alpha
    else:
        raise ValueError(kind)
    a0, a1, a2 = 1 + alpha, -2 * cw, 1 - alpha
    b0, b1, b2, a1, a2 = b0 / a0, b1 / a0, b2 / a0, a1 / a0, a2 / a0
    x1 = x2 = y1 = y2 = 0.0
    passes = 2 if circular else 1
    out = [0.0] * len(x)
    for p in range(passes):
        for i, v in enumerate(x):
            y = b0 * v + b1 * x1 + b2 * x2 - a1 * y1 - a2 * y2
            x2, x1, y2, y1 = x1, v, y1, y
            if p == passes - 1:
                out[i] = y
    return out


def modes(partials, dur, attack=0.0005):
    """Sum of exponentially damped sinusoids: [(freq, amp, tau), ...]."""
    n = n_of(dur)
    out = zeros(n)
    na = max(1, n_of(attack))
    for f, a, tau in partials:
        w = TWO_PI * f / SR
        d = math.exp(-1.0 / (tau * SR))
        env = a
        for i in range(n):
            out[i] += env * math.sin(w * i)
            env *= d
    for i in range(min(na, n)):
        out[i] *= i / na
    return out


def decay_env(x, tau, attack=0.0):
    d = math.exp(-1.0 / (tau * SR))
    na = n_of(attack)
    env = 1.0
    out = [0.0] * len(x)
    for i, v in enumerate(x):
        g = env
        if i < na:
            g *= i / na
        out[i] = v * g
        env *= d
    return out


def fade(x, fin=0.002, fout=0.010):
    n = len(x)
    ni, no = min(n, n_of(fin)), min(n, n_of(fout))
    y = list(x)
    for i in range(ni):
        y[i] *= 0.5 - 0.5 * math.cos(math.pi * i / ni)
    for i in range(no):
        y[n - 1 - i] *= 0.5 - 0.5 * math.cos(math.pi * i / no)
    return y


def normalise(x, peak=PEAK):
    m = max((abs(v) for v in x), default=0.0)
    if m == 0.0:
        return list(x)
    g = peak / m
    return [v * g for v in x]


def rotate_to_quiet_zero_crossing(x):
    """For loops: rotate circularly so the buffer starts at an upward zero
    crossing in a quiet region (no click at first start, loop unchanged)."""
    n = len(x)
    # short-term energy over 10 ms windows, evaluated every 5 ms
    win, hop = n_of(0.010), n_of(0.005)
    best, best_e = 0, None
    for s in range(0, n, hop):
        e = 0.0
        for k in range(win):
            v = x[(s + k) % n]
            e += v * v
        if best_e is None or e < best_e:
            best, best_e = s, e
    start, step = best, None
    for k in range(win * 2):
        i = (start + k) % n
        if x[i - 1] < 0.0 <= x[i]:
            jump = x[i] - x[i - 1]
            if step is None or jump < step:
                best, step = i, jump
    return x[best:] + x[:best]


def to_pcm16(x):
    out = bytearray()
    for v in x:
        s = int(round(v * 32767.0))
        s = 32767 if s > 32767 else (-32768 if s < -32768 else s)
        out += struct.pack("<h", s)
    return bytes(out)


def write_wav(path, x):
    with wave.open(path, "wb") as w:
        w.setnchannels(1)
        w.setsampwidth(2)
        w.setframerate(SR)
        w.writeframes(to_pcm16(x))


def read_wav(path):
    with wave.open(path, "rb") as w:
        ch, sw, fr, nf = w.getnchannels(), w.getsampwidth(), w.getframerate(), w.getnframes()
        data = w.readframes(nf)
    if sw != 2:
        raise RuntimeError(f"{path}: expected 16-bit samples, got {8 * sw}-bit")
    s = struct.unpack("<%dh" % (len(data) // 2), data)
    if ch > 1:
        s = [sum(s[i:i + ch]) / ch for i in range(0, len(s), ch)]
    x = [v / 32768.0 for v in s]
    if fr != SR:
        x = resample_linear(x, fr, SR)
    return x


def resample_linear(x, fr_in, fr_out):
    n = int(len(x) * fr_out / fr_in)
    out = []
    for i in range(n):
        p = i * fr_in / fr_out
        j = int(p)
        f = p - j
        a = x[j] if j < len(x) else 0.0
        b = x[j + 1] if j + 1 < len(x) else 0.0
        out.append(a + (b - a) * f)
    return out


# --------------------------------------------------------------------------
# synthesised sounds
# --------------------------------------------------------------------------

def ball_racket():
    """0: tennis ball hitting the strings - short bright 'pock'."""
    rng = random.Random(1000)
    dur = 0.16
    x = modes([
        (560.0, 1.00, 0.010),   # ball shell
        (1180.0, 0.70, 0.007),
        (1950.0, 0.45, 0.004),
        (2950.0, 0.25, 0.0025),
        (640.0, 0.30, 0.035),   # string-bed ping
        (150.0, 0.25, 0.025),   # frame
    ], dur)
    n = len(x)
    burst = decay_env(biquad(white(rng, n), "bp", 2400.0, 0.7), 0.0018)
    add_into(x, burst, 0, 2.5)
    return fade(x, 0.0003, 0.015)


def ball_ground():
    """1: ball bouncing on the court - duller, lower 'pung'."""
    rng = random.Random(1001)
    dur = 0.20
    x = modes([
        (310.0, 1.00, 0.016),
        (830.0, 0.50, 0.008),
        (1520.0, 0.25, 0.004),
        (105.0, 0.55, 0.022),   # ground thud
    ], dur, attack=0.001)
    n = len(x)
    burst = decay_env(lowpass1(white(rng, n), 1500.0), 0.004)
    add_into(x, burst, 0, 1.8)
    return fade(x, 0.0005, 0.020)


def ball_net():
    """9: ball into the net - soft thud plus rustle of the net."""
    rng = random.Random(1009)
    dur = 0.50
    n = n_of(dur)
    x = modes([(95.0, 0.8, 0.035), (230.0, 0.45, 0.020), (480.0, 0.15, 0.010)],
              dur, attack=0.004)
    thud_noise = decay_env(lowpass1(lowpass1(white(rng, n), 700.0), 700.0), 0.025, 0.003)
    add_into(x, thud_noise, 0, 2.0)
    # rustle: band-passed noise, continuous part plus sparse grains (cords)
    rustle = decay_env(biquad(white(rng, n), "bp", 3200.0, 0.8), 0.09, 0.010)
    add_into(x, rustle, n_of(0.005), 0.35)
    grains = zeros(n)
    t = 0.008
    while t < dur - 0.02:
        g = decay_env(white(rng, n_of(0.006)), 0.0015)
        add_into(grains, g, n_of(t), math.exp(-t / 0.12) * (0.5 + rng.random()))
        t += 0.004 + rng.random() * 0.02 * (1.0 + t * 6.0)
    add_into(x, biquad(grains, "bp", 4500.0, 0.7), 0, 0.6)
    return fade(x, 0.002, 0.030)


def cricket():
    """2: a field cricket chirping for ~3 s."""
    rng = random.Random(1002)
    dur = 3.0
    n = n_of(dur)
    x = zeros(n)
    t = 0.08
    while t < dur - 0.2:
        npulse = 3 + (1 if rng.random() < 0.5 else 0)
        level = 0.75 + 0.25 * rng.random()
        for p in range(npulse):
            pl = 0.016
            m = n_of(pl)
            f0 = 4700.0 + rng.random() * 60.0
            ph = 0.0
            pulse = [0.0] * m
            for i in range(m):
                u = i / m
                f = f0 - 220.0 * u  # small downward glide in each pulse
                ph += TWO_PI * f / SR
                env = math.sin(math.pi * u) ** 2
                pulse[i] = env * (math.sin(ph) + 0.12 * math.sin(2.0 * ph))
            add_into(x, pulse, n_of(t + p * 0.032), level)
        t += 0.36 + rng.random() * 0.08
    return fade(x, 0.005, 0.030)


def additive_voice(f0_of_t, amp_of_f, dur, env_of_t, max_f=9000.0):
    """Harmonic source with time-varying pitch; amp_of_f is a spectral
    envelope (so formants stay fixed while the pitch moves)."""
    n = n_of(dur)
    out = [0.0] * n
    ph = 0.0
    for i in range(n):
        t = i / SR
        f0 = f0_of_t(t)
        ph += TWO_PI * f0 / SR
        e = env_of_t(t)
        if e <= 0.0:
            continue
        s = 0.0
        h = 1
        while h * f0 < max_f:
            s += amp_of_f(h * f0) * math.sin(h * ph)
            h += 1
        out[i] = e * s
    return out


def frog():
    """4: a frog croaking 'rib-bit' twice."""
    def formants(f):
        a = 0.0
        for fc, bw, g in ((550.0, 180.0, 1.0), (1400.0, 300.0, 0.7), (2300.0, 500.0, 0.25)):
            a += g / (1.0 + ((f - fc) / bw) ** 2)
        return a

    def syllable(dur, f_start, f_end, rate):
        def f0(t):
            return f_start + (f_end - f_start) * t / dur

        def env(t):
            # rattle: the croak is a train of rapid pulses
            u = (t * rate) % 1.0
            gate = math.sin(math.pi * min(u / 0.7, 1.0)) ** 2 if u < 0.7 else 0.0
            a = min(1.0, t / 0.012) * min(1.0, (dur - t) / 0.025)
            return max(0.0, a) * gate
        return additive_voice(f0, formants, dur, env, max_f=5000.0)

    x = zeros(n_of(1.45))
    for start, lvl in ((0.04, 1.0), (0.78, 0.85)):
        add_into(x, syllable(0.13, 190.0, 165.0, 28.0), n_of(start), lvl)
        add_into(x, syllable(0.19, 215.0, 150.0, 24.0), n_of(start + 0.20), lvl)
    return fade(x, 0.003, 0.030)


def foret():
    """5: tropical forest ambience, 6 s, seamless loop (all events are placed
    circularly and the noise beds are filtered circularly)."""
    rng = random.Random(1005)
    dur = 6.0
    n = n_of(dur)
    x = zeros(n)

    # rustle / wind in the leaves: slowly modulated low-passed noise
    bed = biquad(biquad(white(rng, n), "lp", 700.0, 0.7, True), "hp", 150.0, 0.7, True)
    for i in range(n):
        u = i / n
        bed[i] *= 0.75 + 0.25 * math.sin(TWO_PI * 2 * u) + 0.12 * math.sin(TWO_PI * 5 * u + 1.0)
    add_into(x, bed, 0, 0.55)

    # leaf crackles
    crack = zeros(n)
    for _ in range(60):
        g = decay_env(white(rng, n_of(0.008)), 0.0015)
        add_into(crack, g, int(rng.random() * n), 0.2 + 0.5 * rng.random(), wrap=True)
    add_into(x, biquad(crack, "bp", 3800.0, 0.8, True), 0, 0.35)

    # insects: a cicada-like pulsed buzz and a slower trill (integer numbers
    # of cycles per loop keep the loop seamless)
    cyc = lambda f: round(f * dur) / dur
    fa, fb, ra = cyc(6200.0), cyc(6450.0), cyc(45.0)
    fc, rc, sc = cyc(3900.0), cyc(17.0), cyc(0.5)
    for i in range(n):
        t = i / SR
        am = 0.5 + 0.5 * math.sin(TWO_PI * ra * t)
        buzz = am * am * (math.sin(TWO_PI * fa * t) + 0.6 * math.sin(TWO_PI * fb * t))
        tr = max(0.0, math.sin(TWO_PI * rc * t)) ** 3
        swell = 0.5 + 0.5 * math.sin(TWO_PI * sc * t)
        x[i] += 0.05 * buzz + 0.06 * swell * tr * math.sin(TWO_PI * fc * t)

    # birds
    def tone(dur_s, f_of_u, amp_of_u, h2=0.0):
        m = n_of(dur_s)
        out = [0.0] * m
        ph = 0.0
        for i in range(m):
            u = i / m
            ph += TWO_PI * f_of_u(u) / SR
            out[i] = amp_of_u(u) * (math.sin(ph) + h2 * math.sin(2.0 * ph))
        return out

    bell = lambda u: math.sin(math.pi * u) ** 2

    def whistle_up(lvl):  # rising whistle
        return tone(0.14, lambda u: 2100.0 + 1200.0 * u * u, bell), lvl

    def trill(lvl):  # fast frequency-modulated trill
        return tone(0.55, lambda u: 3400.0 + 500.0 * math.sin(TWO_PI * 22.0 * 0.55 * u) - 400.0 * u,
                    lambda u: bell(u) ** 0.5), lvl

    def whoop(lvl, f=1250.0):  # tropical two-tone descending call
        return tone(0.26, lambda u: f - 320.0 * u, lambda u: bell(u) ** 0.7, 0.25), lvl

    def chip(lvl):  # tiny high chirp
        return tone(0.035, lambda u: 5200.0 - 1500.0 * u, bell), lvl

    def coo(lvl):  # low dove-like coo, far away
        return tone(0.30, lambda u: 620.0 + 60.0 * math.sin(math.pi * u), lambda u: bell(u) ** 0.6, 0.15), lvl

    events = []
    for k in range(3):
        events.append((0.30 + k * 0.20, whistle_up(0.55)))
    events.append((1.30, trill(0.40)))
    events.append((2.10, whoop(0.55)))
    events.append((2.45, whoop(0.50, 1050.0)))
    events.append((2.95, coo(0.35)))
    events.append((3.40, coo(0.30)))
    for k in range(3):
        events.append((3.80 + k * 0.20, whistle_up(0.40)))
    events.append((4.55, trill(0.30)))
    events.append((5.30, whoop(0.38)))
    events.append((5.65, whoop(0.34, 1050.0)))
    for _ in range(18):
        events.append((rng.random() * dur, chip(0.12 + 0.18 * rng.random())))
    for t, (sig, lvl) in events:
        add_into(x, sig, n_of(t), lvl, wrap=True)

    return rotate_to_quiet_zero_crossing(x)


def start_beep():
    """6: 10 ms synchronisation beep."""
    n = n_of(0.010)
    x = [math.sin(TWO_PI * 2000.0 * i / SR) for i in range(n)]
    return fade(x, 0.001, 0.002)


def karplus_strong(freq, dur, rng, decay=0.996, bright=0.5):
    n = n_of(dur)
    p = max(2, int(round(SR / freq - 0.5)))
    buf = [rng.random() * 2.0 - 1.0 for _ in range(p)]
    # soften the excitation a little
    buf = [(1 - bright) * buf[i - 1] + bright * buf[i] for i in range(p)]
    out = [0.0] * n
    idx = 0
    for i in range(n):
        a = buf[idx]
        b = buf[(idx + 1) % p]
        out[i] = a
        buf[idx] = decay * 0.5 * (a + b)
        idx = (idx + 1) % p
    return out


def midi_hz(m):
    return 440.0 * 2.0 ** ((m - 69) / 12.0)


def violin_note(freq, dur, level):
    amps = [1.0, 0.62, 0.46, 0.34, 0.27, 0.20, 0.15, 0.12, 0.09, 0.07, 0.05, 0.04]
    n = n_of(dur + 0.08)
    out = [0.0] * n
    ph = 0.0
    att, rel = 0.025, 0.07
    for i in range(n):
        t = i / SR
        vib = 1.0 + 0.004 * min(1.0, max(0.0, (t - 0.10) / 0.15)) * math.sin(TWO_PI * 5.6 * t)
        ph += TWO_PI * freq * vib / SR
        if t < att:
            e = t / att
        elif t < dur:
            e = 1.0 - 0.15 * (t - att) / max(dur, 1e-3)
        else:
            e = (1.0 - 0.15) * max(0.0, 1.0 - (t - dur) / rel)
        if e <= 0.0:
            continue
        s = 0.0
        for h, a in enumerate(amps, 1):
            if h * freq * vib >= SR * 0.45:
                break
            s += a * math.sin(h * ph)
        out[i] = level * e * s
    return out


def schroeder_reverb(x, wet=0.18):
    combs = [(1116, 0.78), (1188, 0.77), (1277, 0.76), (1356, 0.75)]
    n = len(x)
    acc = [0.0] * n
    for d, g in combs:
        d = d * SR // 44100
        buf = [0.0] * d
        j = 0
        lp = 0.0
        for i in range(n):
            y = buf[j]
            lp = 0.6 * y + 0.4 * lp  # damping
            buf[j] = x[i] + g * lp
            acc[i] += y
            j = (j + 1) % d
    for d, g in ((556, 0.5), (441, 0.5)):
        d = d * SR // 44100
        buf = [0.0] * d
        j = 0
        out = [0.0] * n
        for i in range(n):
            b = buf[j]
            y = -acc[i] + b
            buf[j] = acc[i] + g * b
            out[i] = y
            j = (j + 1) % d
        acc = out
    return [a + wet * 0.25 * r for a, r in zip(x, acc)]


def vivaldi():
    """7: opening ritornello of the Allegro of Vivaldi's 'Spring' (RV 269,
    public domain), E major: phrase a loud, a echoed softly, phrase b loud
    with a cadence; two violins in thirds over a plucked bass."""
    rng = random.Random(1007)
    bpm = 126.0
    beat = 60.0 / bpm
    E4, Fs4, Gs4, A4, B4, Cs5, Ds5, E5, Fs5, Gs5, A5, B5 = 64, 66, 68, 69, 71, 73, 75, 76, 78, 80, 81, 83
    B2, E3 = 47, 52
    motif = [(Gs5, .5), (Gs5, .5), (Gs5, .5), (Fs5, .25), (E5, .25), (B5, 1.5), (B5, .25), (A5, .25)]
    melody = [(E5, .5)] + motif + motif + [
        (Gs5, .5), (A5, .5), (B5, .5), (A5, .5), (Gs5, .5), (Fs5, .5), (Ds5, .5), (B4, .5),
        (E5, 2.0)]
    third_below = {E5: Cs5, Fs5: Ds5, Gs5: E5, A5: Fs5, B5: Gs5, Ds5: B4, B4: Gs4}
    second = [(third_below[m], d) for m, d in melody[:-1]] + [(Gs4, 2.0)]
    second[0] = (B4, .5)
    bass = [(E3, .5)] * 16 + [(E3, .5)] * 4 + [(B2, .5)] * 4 + [(E3 - 12, 2.0)]

    def dynamic(t_beats):  # forte, piano echo of phrase a (beats 4.5..8.5), forte
        return 0.45 if 4.5 <= t_beats < 8.5 else 1.0

    total = sum(d for _, d in melody) * beat + 1.0
    x = zeros(n_of(total))
    tb = 0.0
    for m, d in melody:
        add_into(x, violin_note(midi_hz(m), d * beat * 0.93, 0.30 * dynamic(tb)), n_of(tb * beat))
        tb += d
    tb = 0.0
    for m, d in second:
        add_into(x, violin_note(midi_hz(m), d * beat * 0.93, 0.17 * dynamic(tb)), n_of(tb * beat))
        tb += d
    tb = 0.5  # bass enters on the downbeat after the pick-up
    for m, d in bass:
        note = karplus_strong(midi_hz(m), d * beat + 0.3, rng, 0.994 if d < 1 else 0.998)
        note = fade(note, 0.002, 0.05)
        add_into(x, note, n_of(tb * beat), (0.55 if d < 1 else 0.7) * dynamic(tb))
        tb += d
    x = schroeder_reverb(x)
    return fade(x, 0.002, 0.25)


def avion():
    """8: constant propeller-airplane drone, 4.5 s, seamless loop.  Two
    engines with a clear harmonic tone (blade-pass fundamental ~100 Hz, so
    Doppler shifts are audible) beating slowly, plus broadband noise."""
    rng = random.Random(1008)
    dur = 4.5
    n = n_of(dur)  # 99225 samples
    # integer numbers of cycles per loop -> exactly periodic
    k1, k2 = 450, 452          # 100.0 Hz and 100.44 Hz
    harm = [1.0, 0.85, 0.65, 0.55, 0.38, 0.30, 0.24, 0.20, 0.16, 0.13,
            0.11, 0.09, 0.08, 0.07, 0.06, 0.05, 0.045, 0.04, 0.035, 0.03]
    phases1 = [rng.random() * TWO_PI for _ in harm]
    phases2 = [rng.random() * TWO_PI for _ in harm]
    x = zeros(n)
    for i in range(n):
        u = i / n
        s = 0.0
        for h, a in enumerate(harm, 1):
            s += a * math.sin(TWO_PI * h * k1 * u + phases1[h - 1])
            s += 0.7 * a * math.sin(TWO_PI * h * k2 * u + phases2[h - 1])
        x[i] = s
    m = max(abs(v) for v in x)
    x = [v / m for v in x]
    # broadband: low rumble + exhaust/wind hiss, filtered circularly
    rumble = lowpass1(lowpass1(white(rng, n), 450.0, True), 450.0, True)
    hiss = biquad(white(rng, n), "bp", 1800.0, 0.6, True)
    rm = max(abs(v) for v in rumble)
    hm = max(abs(v) for v in hiss)
    for i in range(n):
        x[i] += 0.45 * rumble[i] / rm + 0.12 * hiss[i] / hm
    return rotate_to_quiet_zero_crossing(x)


def silence_20ms():
    """28: exactly 0.02 s of silence (441 samples)."""
    return zeros(n_of(0.02))


SYNTH = [
    ("ball_racket", ball_racket),
    ("ball_ground", ball_ground),
    ("cricket", cricket),
    ("frog", frog),
    ("foret", foret),
    ("start", start_beep),
    ("vivaldi", vivaldi),
    ("avion", avion),
    ("ball_net", ball_net),
]

# No normalisation / fades for these (exact silence).
RAW = [("wait02", silence_20ms)]


# --------------------------------------------------------------------------
# spoken words (espeak-ng)
# --------------------------------------------------------------------------

# file stem -> text spoken
WORDS = [
    # table D.1, 10..27
    ("advantage", "advantage"), ("all", "all"), ("deuce", "deuce"),
    ("fault", "fault"), ("fifteen", "fifteen"), ("fourty", "forty"),
    ("game", "game"), ("let", "let"), ("love", "love"), ("server", "server"),
    ("striker", "striker"), ("thirty", "thirty"), ("blue", "blue"),
    ("green", "green"), ("out", "out"), ("service", "service"),
    ("left", "left"), ("right", "right"),
    # table D.2, 29..58 (46 blue and 47 green are shared with 22/23)
    ("move_right", "move right"), ("move_left", "move left"),
    ("move_up", "move up"), ("move_down", "move down"), ("move", "move"),
    ("go_back", "go back"), ("turn_up", "turn up"),
    ("turn_down", "turn down"), ("turn_left", "turn left"),
    ("turn_right", "turn right"), ("faster", "faster"),
    ("slow_down", "slow down"), ("turn_faster", "turn faster"),
    ("turn_less", "turn less"), ("block", "block"), ("free_it", "free it"),
    ("stop", "stop"), ("one", "one"), ("two", "two"), ("three", "three"),
    ("four", "four"), ("five", "five"), ("six", "six"), ("seven", "seven"),
    ("eight", "eight"), ("nine", "nine"), ("ten", "ten"), ("exit", "exit"),
]

ESPEAK_VOICE = "en"
ESPEAK_SPEED = 150  # words per minute


def trim_silence(x, rel_db=-40.0, pre=0.010, post=0.030):
    m = max((abs(v) for v in x), default=0.0)
    if m == 0.0:
        return list(x)
    thr = m * 10.0 ** (rel_db / 20.0)
    first = next(i for i, v in enumerate(x) if abs(v) > thr)
    last = len(x) - 1 - next(i for i, v in enumerate(reversed(x)) if abs(v) > thr)
    a = max(0, first - n_of(pre))
    b = min(len(x), last + 1 + n_of(post))
    return x[a:b]


def speak(espeak, text, tmpdir):
    path = os.path.join(tmpdir, "w.wav")
    subprocess.run([espeak, "-v", ESPEAK_VOICE, "-s", str(ESPEAK_SPEED), "-w", path, text],
                   check=True)
    x = read_wav(path)
    x = trim_silence(x)
    x = fade(x, 0.005, 0.010)
    return normalise(x)


# --------------------------------------------------------------------------

def main():
    here = os.path.dirname(os.path.abspath(__file__))
    default_out = os.path.join(os.path.dirname(here), "scenes", "sounds")
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=default_out, help="output directory (default: scenes/sounds)")
    ap.add_argument("--no-speech", action="store_true", help="skip the espeak-ng words")
    ap.add_argument("--only", nargs="*", help="generate only these file stems")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    want = set(args.only) if args.only else None

    def wanted(name):
        return want is None or name in want

    for name, fn in SYNTH:
        if wanted(name):
            write_wav(os.path.join(args.out, name + ".wav"), normalise(fn()))
            print("synth ", name + ".wav")
    for name, fn in RAW:
        if wanted(name):
            write_wav(os.path.join(args.out, name + ".wav"), fn())
            print("synth ", name + ".wav")

    if args.no_speech:
        return
    espeak = shutil.which("espeak-ng")
    if espeak is None:
        sys.exit("espeak-ng not found (apt-get install espeak-ng), or use --no-speech")
    with tempfile.TemporaryDirectory() as tmp:
        for name, text in WORDS:
            if wanted(name):
                write_wav(os.path.join(args.out, name + ".wav"), speak(espeak, text, tmp))
                print("speech", name + ".wav")


if __name__ == "__main__":
    main()
