use super::*;
use std::fs::File;
use std::io::BufReader;

/// Frame `i` of a moving test card: a gradient with a bright square that moves.
fn card(i: u32, w: u32, h: u32) -> Vec<u8> {
    let mut rgb = Vec::with_capacity((w * h * 3) as usize);
    for y in 0..h {
        for x in 0..w {
            let inside = (x + 40 - 3 * i % 40) % 40 < 8 && y % 16 < 8;
            let v = if inside { 255 } else { (x * 255 / w) as u8 };
            rgb.extend_from_slice(&[v, (y * 255 / h) as u8, 128]);
        }
    }
    rgb
}

fn write(format: VideoFormat, name: &str, count: u32, fps: f64) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    let info = encode(
        format,
        &path,
        (32, 18),
        fps,
        count,
        &mut |i| Ok(card(i, 32, 18)),
        &|| {},
    )
    .unwrap();
    assert_eq!(info.frames, count);
    assert_eq!(info.bytes, std::fs::metadata(&path).unwrap().len());
    // Only the video is left in the folder.
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    (dir, path)
}

use std::path::PathBuf;

#[test]
#[cfg(feature = "h264")]
fn mp4_has_every_frame_at_the_right_size_and_rate() {
    let (_dir, path) = write(VideoFormat::Mp4, "a.mp4", 10, 24.0);
    let size = std::fs::metadata(&path).unwrap().len();
    let reader = BufReader::new(File::open(&path).unwrap());
    let mut mp4 = ::mp4::Mp4Reader::read_header(reader, size).unwrap();
    assert_eq!(mp4.tracks().len(), 1);
    let track = mp4.tracks().get(&1).unwrap();
    assert_eq!((track.width(), track.height()), (32, 18));
    assert_eq!(track.sample_count(), 10);
    assert_eq!(track.timescale(), 24000);
    assert!(
        (track.frame_rate() - 24.0).abs() < 1e-9,
        "{}",
        track.frame_rate()
    );
    assert_eq!(track.duration().as_millis(), 416);
    // The movie's duration is as exact as the track's: 10 frames at 24 fps.
    assert_eq!(mp4.timescale(), 24000);
    assert_eq!(mp4.moov.mvhd.duration, 10_000);
    assert_eq!(track.media_type().unwrap(), ::mp4::MediaType::H264);
    // The SPS carries the colour description: BT.601 (SMPTE 170M) in its VUI.
    let sps = track.sequence_parameter_set().unwrap().to_vec();
    assert_eq!(sps[0] & 0x1f, 7);
    // So does the container: a colr box of type nclx, codes 6 6 6, limited range.
    let bytes = std::fs::read(&path).unwrap();
    let at = bytes.windows(8).position(|w| w == b"colrnclx").unwrap();
    assert_eq!(&bytes[at - 4..at], &19u32.to_be_bytes());
    assert_eq!(&bytes[at + 8..at + 15], &[0, 6, 0, 6, 0, 6, 0]);
    let first = mp4.read_sample(1, 1).unwrap().unwrap();
    assert!(first.is_sync, "the first frame is a key frame");
    for i in 1..=10 {
        let s = mp4.read_sample(1, i).unwrap().unwrap();
        assert!(!s.bytes.is_empty(), "sample {i} is empty");
        assert_eq!(s.start_time, (i as u64 - 1) * 1000);
    }
}

/// Without the encoder, MP4 output is refused by name and leaves no file.
#[test]
#[cfg(not(feature = "h264"))]
fn mp4_without_h264_is_refused_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("a.mp4");
    let e = encode(
        VideoFormat::Mp4,
        &path,
        (32, 18),
        24.0,
        2,
        &mut |i| Ok(card(i, 32, 18)),
        &|| {},
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("a.mp4") && e.contains("without H.264"), "{e}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn mp4_needs_even_sides() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("odd.mp4");
    let e = encode(
        VideoFormat::Mp4,
        &path,
        (31, 18),
        24.0,
        1,
        &mut |_| Ok(vec![0; 31 * 18 * 3]),
        &|| {},
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("even width and height, found 31x18"), "{e}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn gif_decodes_to_the_frames_with_hundredths_of_a_second() {
    let (_dir, path) = write(VideoFormat::Gif, "a.gif", 6, 24.0);
    let mut options = ::gif::DecodeOptions::new();
    options.set_color_output(::gif::ColorOutput::RGBA);
    let mut decoder = options.read_info(File::open(&path).unwrap()).unwrap();
    assert_eq!((decoder.width(), decoder.height()), (32, 18));
    let mut frames = 0;
    while let Some(frame) = decoder.read_next_frame().unwrap() {
        assert_eq!((frame.width, frame.height), (32, 18));
        // 24 fps is 4.17 hundredths: 4, 4, 5, 4, 4, 4 keeps time (25 hundredths in all).
        assert_eq!(
            frame.delay,
            [4, 4, 5, 4, 4, 4][frames as usize],
            "frame {frames}"
        );
        // The frame is the card, up to the 256-colour palette (576 colours here).
        let card = card(frames, 32, 18);
        let rgb = frame.buffer.chunks(4).flat_map(|p| &p[..3]);
        let diff: u32 = rgb.zip(&card).map(|(&a, &b)| a.abs_diff(b) as u32).sum();
        let mean = diff as f64 / card.len() as f64;
        assert!(mean < 16.0, "frame {frames}: mean difference {mean}");
        frames += 1;
    }
    assert_eq!(frames, 6);
    // The whole film lasts exactly as long as asked: 120 frames at 24 fps, 5 s.
    let total = |n: u64, fps: f64| (0..n).map(|k| gif::delay_for(k, fps) as u64).sum::<u64>();
    assert_eq!(total(120, 24.0), 500);
    assert_eq!(total(30, 30.0), 100);
    assert_eq!(total(7, 0.01), 70_000);
    assert_eq!(gif::delay_for(0, 25.0), 4);
    assert_eq!(gif::delay_for(0, 100.0), 1);
    assert!(gif_timing_note(24.0).unwrap().contains("4 or 5 hundredths"));
    assert!(gif_timing_note(60.0).unwrap().contains("browsers"));
    assert_eq!(gif_timing_note(25.0), None);
}

#[test]
fn apng_decodes_to_the_exact_frames() {
    let (_dir, path) = write(VideoFormat::Apng, "a.png", 5, 12.0);
    let decoder = ::png::Decoder::new(BufReader::new(File::open(&path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let control = reader.info().animation_control().unwrap();
    assert_eq!((control.num_frames, control.num_plays), (5, 0));
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    for i in 0..5 {
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), (32, 18));
        assert_eq!(&buf[..info.buffer_size()], card(i, 32, 18), "frame {i}");
        let fc = reader.info().frame_control().unwrap();
        assert_eq!((fc.delay_num, fc.delay_den), (1, 12));
    }
    assert_eq!(apng::delay_for(29.97), (1000, 29970));
    assert_eq!(apng::delay_for(23.976), (1000, 23976));
    assert_eq!(apng::delay_for(24.0), (1, 24));
    assert_eq!(apng::delay_for(1000.0), (1, 1000));
    // Slow rates are delays of many seconds, not a clamped 1 fps.
    assert_eq!(apng::delay_for(0.01), (100, 1));
    assert_eq!(apng::delay_for(0.5), (2, 1));
    let (n, d) = apng::delay_for(0.03);
    assert!((n as f64 / d as f64 - 1.0 / 0.03).abs() < 1e-3, "{n}/{d}");
    let (n, d) = apng::delay_for(123.456);
    assert!((d as f64 / n as f64 - 123.456).abs() < 0.01, "{n}/{d}");
}

#[test]
fn mp4_needs_sixteen_pixels_a_side() {
    for (w, h) in [(14, 18), (32, 8)] {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("small.mp4");
        let e = encode(
            VideoFormat::Mp4,
            &path,
            (w, h),
            24.0,
            1,
            &mut |_| Ok(vec![0; (w * h * 3) as usize]),
            &|| {},
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains(&format!("at least 16x16, found {w}x{h}")), "{e}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }
}

#[test]
#[cfg(feature = "h264")]
fn mp4_refuses_a_rate_it_cannot_keep_and_keeps_slow_rates() {
    let mut out = std::io::Cursor::new(Vec::new());
    let e = mp4::Mp4::new(&mut out, std::path::Path::new("a.mp4"), 32, 18, 0.0004)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("0.0004 fps"), "{e}");
    // The slowest rate an animation file accepts encodes, and lasts 100 s a frame.
    let (_dir, path) = write(VideoFormat::Mp4, "slow.mp4", 2, crate::anim::MIN_FPS);
    let size = std::fs::metadata(&path).unwrap().len();
    let reader = BufReader::new(File::open(&path).unwrap());
    let mp4 = ::mp4::Mp4Reader::read_header(reader, size).unwrap();
    assert_eq!(mp4.duration().as_secs(), 200);
}
