//! How fast OBJ files load, on one thread and on two.
//!
//! `cargo run --release --example obj_load -- FILE.obj... [--rounds N]`
//!
//! For each file, each round times, on a one-thread and on a two-thread pool: the OBJ
//! reader alone on the bytes already in memory (`parse`), and what `prism info` does
//! to read it (`load`: the file read, parsed and made a scene). The table gives the
//! median of the rounds as MB/s of OBJ text (1 MB = 10^6 bytes); alternating the pools
//! round by round (each going first in turn) keeps a busy machine's swings out of the
//! ratio.

use std::path::PathBuf;
use std::time::Instant;

fn main() {
    let mut rounds = 7;
    let mut files = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        if arg == "--rounds" {
            rounds = args
                .next()
                .and_then(|n| n.parse().ok())
                .expect("--rounds needs a number");
        } else {
            files.push(PathBuf::from(arg));
        }
    }
    if files.is_empty() {
        eprintln!("usage: obj_load FILE.obj... [--rounds N]");
        std::process::exit(2);
    }
    let pools: Vec<(usize, rayon::ThreadPool)> = [1, 2]
        .into_iter()
        .map(|n| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .expect("thread pool");
            (n, pool)
        })
        .collect();
    println!("| file | MB | threads | parse MB/s | load MB/s |");
    println!("|---|---:|---:|---:|---:|");
    for path in &files {
        let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let mb = bytes.len() as f64 / 1e6;
        let mut parse = vec![Vec::new(); pools.len()];
        let mut load = vec![Vec::new(); pools.len()];
        for round in 0..rounds {
            // Whichever pool goes first meets the memory the other left: take turns.
            let mut order: Vec<usize> = (0..pools.len()).collect();
            if round % 2 == 1 {
                order.reverse();
            }
            for k in order {
                let pool = &pools[k].1;
                pool.install(|| {
                    let start = Instant::now();
                    let obj = prism::format::obj::parse_obj(&bytes, path).expect("parse");
                    parse[k].push(start.elapsed().as_secs_f64());
                    drop(obj);
                    let start = Instant::now();
                    let scene = prism::format::load(path).expect("load");
                    load[k].push(start.elapsed().as_secs_f64());
                    drop(scene);
                });
            }
        }
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        for (k, (threads, _)) in pools.iter().enumerate() {
            println!(
                "| {name} | {mb:.1} | {threads} | {:.0} | {:.0} |",
                mb / median(&mut parse[k]),
                mb / median(&mut load[k])
            );
        }
    }
}

fn median(times: &mut [f64]) -> f64 {
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}
