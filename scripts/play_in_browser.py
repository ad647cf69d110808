#!/usr/bin/env python3
"""Plays a film's MP4 in headless Chromium (Debian's `chromium`) and checks
what the browser reports: the video element loads it, its width, height
and duration are the film's, it has an audio track, and it plays to the
end. Where `ffprobe` exists, its streams are checked too (H.264 and Opus,
the frame count).

    scripts/play_in_browser.py renders/lmfilm [--timeout 120]

The film folder gives what to expect: its name, size and frame count
from derive.json and settings.json. Exit 0 when every check holds, 1
otherwise, 2 when Chromium is missing. Nothing outside a temporary
profile folder is written.
"""
import argparse
import http.server
import json
import os
import shutil
import socketserver
import subprocess
import sys
import tempfile
import threading
import urllib.parse

PAGE = """<!doctype html><meta charset="utf-8"><title>lmfilm</title>
<video id="v" src="/film.mp4" muted playsinline preload="auto"></video>
<script>
const v = document.getElementById('v');
const said = {};
function tell(extra) {
  Object.assign(said, extra);
  fetch('/result?' + encodeURIComponent(JSON.stringify(said)));
}
v.addEventListener('loadedmetadata', () => {
  said.width = v.videoWidth; said.height = v.videoHeight;
  said.duration = v.duration;
  said.audioTracks = v.audioTracks ? v.audioTracks.length : null;
  v.playbackRate = 4;
  v.play().catch(e => tell({error: 'play: ' + e}));
});
v.addEventListener('ended', () => tell({ended: true, currentTime: v.currentTime,
  audioBytes: v.webkitAudioDecodedByteCount, videoBytes: v.webkitVideoDecodedByteCount,
  frames: v.getVideoPlaybackQuality ? v.getVideoPlaybackQuality().totalVideoFrames : null}));
v.addEventListener('error', () => tell({error: 'media error ' + (v.error && v.error.code) + ' ' + (v.error && v.error.message)}));
</script>"""


def expected(folder):
    derive = json.load(open(os.path.join(folder, "derive.json")))
    settings = json.load(open(os.path.join(folder, "settings.json")))
    name = derive["inputs"]["name"]
    render = settings["render"]
    frames = derive["frame_count"]
    return name, render["width"], render["height"], frames, frames * derive["dt"]


def serve(mp4, results):
    class Handler(http.server.BaseHTTPRequestHandler):
        def log_message(self, *args):
            pass

        def do_GET(self):
            url = urllib.parse.urlparse(self.path)
            if url.path == "/":
                body, kind = PAGE.encode(), "text/html"
            elif url.path == "/film.mp4":
                body, kind = open(mp4, "rb").read(), "video/mp4"
            elif url.path == "/result":
                results.append(json.loads(urllib.parse.unquote(url.query)))
                body, kind = b"ok", "text/plain"
            else:
                self.send_error(404)
                return
            start, end = 0, len(body)
            ranged = self.headers.get("Range", "")
            if ranged.startswith("bytes="):
                a, _, b = ranged[6:].partition("-")
                start, end = int(a or 0), int(b) + 1 if b else len(body)
                self.send_response(206)
                self.send_header("Content-Range", f"bytes {start}-{end - 1}/{len(body)}")
            else:
                self.send_response(200)
            self.send_header("Content-Type", kind)
            self.send_header("Accept-Ranges", "bytes")
            self.send_header("Content-Length", str(end - start))
            self.end_headers()
            self.wfile.write(body[start:end])

    server = socketserver.ThreadingTCPServer(("127.0.0.1", 0), Handler)
    server.daemon_threads = True
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("folder")
    ap.add_argument("--timeout", type=float, default=120)
    args = ap.parse_args()
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if not browser:
        print("chromium is not installed (apt-get install chromium)", file=sys.stderr)
        return 2
    name, width, height, frames, duration = expected(args.folder)
    mp4 = os.path.join(args.folder, name + ".mp4")
    failures = []
    if shutil.which("ffprobe"):
        probe = json.loads(subprocess.run(
            ["ffprobe", "-v", "error", "-count_frames", "-show_streams", "-of", "json", mp4],
            check=True, capture_output=True, text=True).stdout)
        codecs = sorted(s["codec_name"] for s in probe["streams"])
        video = [s for s in probe["streams"] if s["codec_type"] == "video"][0]
        print(f"ffprobe: streams {codecs}, {video['nb_read_frames']} frames of {video['width']}x{video['height']}")
        if codecs != ["h264", "opus"]:
            failures.append(f"ffprobe: streams {codecs}, not h264 and opus")
        if int(video["nb_read_frames"]) != frames:
            failures.append(f"ffprobe: {video['nb_read_frames']} frames, the film has {frames}")
    results = []
    server = serve(mp4, results)
    url = f"http://127.0.0.1:{server.server_address[1]}/"
    with tempfile.TemporaryDirectory() as profile:
        chrome = subprocess.Popen(
            [browser, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
             "--no-first-run", "--disable-background-networking", "--disable-component-update",
             "--disable-sync", "--autoplay-policy=no-user-gesture-required",
             "--enable-blink-features=AudioVideoTracks", f"--user-data-dir={profile}", url],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            waited = 0.0
            while waited < args.timeout and not any("ended" in r or "error" in r for r in results):
                threading.Event().wait(0.5)
                waited += 0.5
        finally:
            chrome.kill()
            chrome.wait()
            server.shutdown()
    said = {}
    for r in results:
        said.update(r)
    print(f"chromium: {json.dumps(said, sort_keys=True)}")
    if "error" in said:
        failures.append(f"chromium: {said['error']}")
    if not said.get("ended"):
        failures.append(f"chromium: the video did not play to its end within {args.timeout} s")
    if (said.get("width"), said.get("height")) != (width + width % 2, height + height % 2):
        failures.append(f"chromium: {said.get('width')}x{said.get('height')}, the film is {width}x{height}")
    if abs(said.get("duration", 0) - duration) > 0.05:
        failures.append(f"chromium: {said.get('duration')} s, the film lasts {duration:.3f} s")
    if not (said.get("audioTracks") or 0) >= 1 or not (said.get("audioBytes") or 0) > 0:
        failures.append(f"chromium: no audio track decoded ({said.get('audioTracks')} tracks, {said.get('audioBytes')} bytes)")
    for f in failures:
        print("FAIL " + f, file=sys.stderr)
    if not failures:
        print(f"{mp4}: plays in Chromium, {width}x{height}, {duration:.2f} s, with sound")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
