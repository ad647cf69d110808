//! A reader of the MP4s lmfilm writes, the tests' own (independent of the
//! muxer that wrote them): the tracks, their sample tables, and the H.264
//! samples decoded back by OpenH264's decoder.

use openh264::formats::YUVSource;

/// A box: its type and its payload.
fn boxes(mut data: &[u8]) -> Vec<([u8; 4], &[u8])> {
    let mut out = Vec::new();
    while data.len() >= 8 {
        let size = u32::from_be_bytes(data[..4].try_into().unwrap()) as usize;
        let kind: [u8; 4] = data[4..8].try_into().unwrap();
        let (header, size) = if size == 1 {
            (
                16,
                u64::from_be_bytes(data[8..16].try_into().unwrap()) as usize,
            )
        } else if size == 0 {
            (8, data.len())
        } else {
            (8, size)
        };
        assert!(
            size >= header && size <= data.len(),
            "a box overruns its parent"
        );
        out.push((kind, &data[header..size]));
        data = &data[size..];
    }
    out
}

fn child<'a>(data: &'a [u8], kind: &[u8; 4]) -> Option<&'a [u8]> {
    boxes(data).into_iter().find(|b| &b.0 == kind).map(|b| b.1)
}

fn path<'a>(data: &'a [u8], kinds: &[&[u8; 4]]) -> &'a [u8] {
    kinds.iter().fold(data, |d, k| {
        child(d, k).unwrap_or_else(|| panic!("no {} box", String::from_utf8_lossy(*k)))
    })
}

fn u32_at(d: &[u8], at: usize) -> u32 {
    u32::from_be_bytes(d[at..at + 4].try_into().unwrap())
}

/// One track.
pub struct Track {
    pub handler: [u8; 4],
    /// The sample entry's four letters (`avc1`, `Opus`).
    pub codec: [u8; 4],
    pub width: u32,
    pub height: u32,
    /// An audio track's channels (0 for video).
    pub channels: u16,
    pub timescale: u32,
    pub duration: u64,
    /// Each sample's (offset in the file, size).
    pub samples: Vec<(usize, usize)>,
    /// The avcC's sequence and picture parameter sets.
    pub parameter_sets: Vec<Vec<u8>>,
}

impl Track {
    pub fn duration_seconds(&self) -> f64 {
        self.duration as f64 / f64::from(self.timescale)
    }
}

pub struct Movie {
    pub tracks: Vec<Track>,
}

impl Movie {
    pub fn read(file: &[u8]) -> Movie {
        let top = boxes(file);
        assert_eq!(top[0].0, *b"ftyp", "an MP4 starts with ftyp");
        let moov = child(file, b"moov").expect("a moov box");
        let tracks = boxes(moov)
            .into_iter()
            .filter(|b| &b.0 == b"trak")
            .map(|(_, trak)| read_track(trak))
            .collect();
        Movie { tracks }
    }

    pub fn track(&self, handler: &[u8; 4]) -> &Track {
        self.tracks
            .iter()
            .find(|t| &t.handler == handler)
            .unwrap_or_else(|| panic!("no {} track", String::from_utf8_lossy(handler)))
    }
}

fn read_track(trak: &[u8]) -> Track {
    let tkhd = path(trak, &[b"tkhd"]);
    let (w, h) = if tkhd[0] == 1 {
        (u32_at(tkhd, 88), u32_at(tkhd, 92))
    } else {
        (u32_at(tkhd, 76), u32_at(tkhd, 80))
    };
    let mdhd = path(trak, &[b"mdia", b"mdhd"]);
    let (timescale, duration) = if mdhd[0] == 1 {
        (
            u32_at(mdhd, 20),
            u64::from_be_bytes(mdhd[24..32].try_into().unwrap()),
        )
    } else {
        (u32_at(mdhd, 12), u64::from(u32_at(mdhd, 16)))
    };
    let hdlr = path(trak, &[b"mdia", b"hdlr"]);
    let stbl = path(trak, &[b"mdia", b"minf", b"stbl"]);
    let stsd = path(stbl, &[b"stsd"]);
    let entry = &boxes(&stsd[8..])[0];
    let mut parameter_sets = Vec::new();
    // An audio sample entry: 8 bytes, then 8 reserved, then its channels.
    let channels = match &hdlr[8..12] {
        b"soun" => u16::from_be_bytes([entry.1[16], entry.1[17]]),
        _ => 0,
    };
    if &entry.0 == b"avc1" {
        // The visual sample entry is 78 bytes before its boxes.
        let avcc = path(&entry.1[78..], &[b"avcC"]);
        let mut at = 5;
        let sps = usize::from(avcc[at] & 0x1f);
        at += 1;
        for k in 0..sps + 1 {
            if k == sps {
                let pps = usize::from(avcc[at]);
                at += 1;
                for _ in 0..pps {
                    let n = usize::from(u16::from_be_bytes([avcc[at], avcc[at + 1]]));
                    parameter_sets.push(avcc[at + 2..at + 2 + n].to_vec());
                    at += 2 + n;
                }
                break;
            }
            let n = usize::from(u16::from_be_bytes([avcc[at], avcc[at + 1]]));
            parameter_sets.push(avcc[at + 2..at + 2 + n].to_vec());
            at += 2 + n;
        }
    }
    // Sample sizes, chunks, and samples per chunk.
    let stsz = path(stbl, &[b"stsz"]);
    let count = u32_at(stsz, 8) as usize;
    let sizes: Vec<usize> = if u32_at(stsz, 4) != 0 {
        vec![u32_at(stsz, 4) as usize; count]
    } else {
        (0..count)
            .map(|i| u32_at(stsz, 12 + 4 * i) as usize)
            .collect()
    };
    let offsets: Vec<usize> = match child(stbl, b"stco") {
        Some(stco) => (0..u32_at(stco, 4) as usize)
            .map(|i| u32_at(stco, 8 + 4 * i) as usize)
            .collect(),
        None => {
            let co64 = path(stbl, &[b"co64"]);
            (0..u32_at(co64, 4) as usize)
                .map(|i| {
                    u64::from_be_bytes(co64[8 + 8 * i..16 + 8 * i].try_into().unwrap()) as usize
                })
                .collect()
        }
    };
    let stsc = path(stbl, &[b"stsc"]);
    let runs: Vec<(usize, usize)> = (0..u32_at(stsc, 4) as usize)
        .map(|i| {
            (
                u32_at(stsc, 8 + 12 * i) as usize,
                u32_at(stsc, 12 + 12 * i) as usize,
            )
        })
        .collect();
    let mut samples = Vec::new();
    let mut next = 0;
    for (c, &offset) in offsets.iter().enumerate() {
        let per = runs.iter().rev().find(|r| r.0 <= c + 1).expect("stsc").1;
        let mut at = offset;
        for _ in 0..per {
            if next == sizes.len() {
                break;
            }
            samples.push((at, sizes[next]));
            at += sizes[next];
            next += 1;
        }
    }
    assert_eq!(samples.len(), count, "the chunks hold every sample");
    Track {
        handler: hdlr[8..12].try_into().unwrap(),
        codec: entry.0,
        width: w >> 16,
        height: h >> 16,
        channels,
        timescale,
        duration,
        samples,
        parameter_sets,
    }
}

/// The video track's samples decoded: each picture's luma plane, row
/// after row, `track.width` wide.
pub fn decode_h264(file: &[u8], track: &Track) -> Vec<Vec<u8>> {
    let mut decoder = openh264::decoder::Decoder::new().unwrap();
    let mut pictures = Vec::new();
    let annex_b = |nal: &[u8]| [&[0, 0, 0, 1][..], nal].concat();
    let mut take = |d: openh264::decoder::DecodedYUV| {
        let (w, h) = d.dimensions();
        let stride = d.strides().0;
        pictures.push(
            (0..h)
                .flat_map(|y| d.y()[y * stride..y * stride + w].to_vec())
                .collect(),
        );
    };
    for ps in &track.parameter_sets {
        decoder.decode(&annex_b(ps)).unwrap();
    }
    for &(at, size) in &track.samples {
        // Length-prefixed NAL units, as MP4 holds them.
        let mut sample = Vec::new();
        let mut d = &file[at..at + size];
        while d.len() >= 4 {
            let n = u32_at(d, 0) as usize;
            sample.extend(annex_b(&d[4..4 + n]));
            d = &d[4 + n..];
        }
        if let Some(p) = decoder.decode(&sample).unwrap() {
            take(p);
        }
    }
    for p in decoder.flush_remaining().unwrap() {
        take(p);
    }
    pictures
}
