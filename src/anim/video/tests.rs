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
        assert_eq!(frame.delay, 4, "24 fps is 4.17 hundredths: 4, so 25 fps");
        // The frame is the card, up to the 256-colour palette (576 colours here).
        let card = card(frames, 32, 18);
        let rgb = frame.buffer.chunks(4).flat_map(|p| &p[..3]);
        let diff: u32 = rgb.zip(&card).map(|(&a, &b)| a.abs_diff(b) as u32).sum();
        let mean = diff as f64 / card.len() as f64;
        assert!(mean < 16.0, "frame {frames}: mean difference {mean}");
        frames += 1;
    }
    assert_eq!(frames, 6);
    assert_eq!(gif::delay_for(24.0), 4);
    assert_eq!(gif::delay_for(30.0), 3);
    assert_eq!(gif::delay_for(100.0), 2);
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
    assert_eq!(apng::delay_for(29.97), (100, 2997));
}
