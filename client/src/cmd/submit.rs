//! `luxfarm submit SCENE... [--haltspp N] [--halttime S] [--haltthreshold T] [--seed S]
//! [--priority P] [--frame N | --frames A-B[:step]] [--policy spread|earliest] [--tag T]...
//! [--min-memory-mb M] [--max-workers W] [--webhook URL] [--watch]`: bundles each scene with
//! every file it references and queues a job, or a frame sequence.
//!
//! ```text
//! one scene                         -> one job
//! one scene --frames A-B[:step]     -> a sequence: one job per frame of the animated scene
//!                                      (LightWave), the bundle made once (the master stores
//!                                      it once, by content)
//! several numbered scenes           -> a sequence: frames/shot_0001.lxs, shot_0002.lxs, ...
//!   (as LuxRender exporters write)     one job per file, frame number from the file name
//! ```
//!
//! A sequence is created on the master first (name: `--name`, else the scenes' common stem;
//! policy: `--policy`); its frames are named `NAME_0001` and their outputs `NAME_0001.png`.
//! The sequence id is printed first (`sequence ID`), then one job id per line.

use super::farm_remote::{job_line, runtime, status, Remote};
use super::frames::FrameRange;
use luxfarm_proto as pb;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// The scene (.lxs, .igs, .lws or .mi, bundled with what it references) or a ready
    /// .zip/.tar bundle; several numbered scene files (`frames/*.lxs`) make a frame sequence.
    #[arg(required = true, num_args = 1..)]
    pub scenes: Vec<PathBuf>,
    #[command(flatten)]
    pub remote: Remote,
    /// Job name (default: the scene's file stem); a sequence's name.
    #[arg(long)]
    pub name: Option<String>,
    #[arg(long)]
    pub haltspp: Option<f64>,
    #[arg(long)]
    pub halttime: Option<f64>,
    #[arg(long)]
    pub haltthreshold: Option<f64>,
    #[arg(long)]
    pub seed: Option<u64>,
    /// 0 to 100; higher runs first.
    #[arg(long)]
    pub priority: Option<i32>,
    /// The scene inside a .zip/.tar holding several.
    #[arg(long)]
    pub scene_in_bundle: Option<String>,
    /// The animation frame to render (animated scene formats).
    #[arg(long, allow_negative_numbers = true, conflicts_with = "frames")]
    pub frame: Option<i64>,
    /// Submit a sequence of one job per frame: `A-B` or `A-B:step` (inclusive), e.g. `1-120`
    /// or `0-96:4`.
    #[arg(long, allow_hyphen_values = true)]
    pub frames: Option<FrameRange>,
    /// How a sequence gives workers frames: `spread` (over the unfinished frames) or
    /// `earliest` (piled on the earliest unfinished frame).
    #[arg(long, default_value = "spread")]
    pub policy: String,
    /// A tag workers must have to take the jobs (repeat for several).
    #[arg(long = "tag")]
    pub tags: Vec<String>,
    /// Memory (MiB) workers must have to take the jobs.
    #[arg(long)]
    pub min_memory_mb: Option<u64>,
    /// The most workers on each job at once.
    #[arg(long)]
    pub max_workers: Option<u32>,
    /// A URL (http or https) the master posts each job's end to (events done, failed,
    /// cancelled, halted), besides its own `--webhook`.
    #[arg(long)]
    pub webhook: Option<String>,
    /// Follow the jobs until they end (as `luxfarm watch`).
    #[arg(long)]
    pub watch: bool,
}

/// A numbered scene file: `shot_0012.lxs` -> ("shot", 12). None without trailing digits.
pub fn numbered(path: &Path) -> Option<(String, i64)> {
    let stem = path.file_stem()?.to_str()?;
    let digits = stem.len() - stem.trim_end_matches(|c: char| c.is_ascii_digit()).len();
    if digits == 0 || digits > 18 {
        return None;
    }
    let (base, number) = stem.split_at(stem.len() - digits);
    let number = number.parse().ok()?;
    Some((base.trim_end_matches(['_', '-', '.']).to_string(), number))
}

/// The frames of numbered scene files, ordered by number; an error names a file without a
/// number, two files with one number, or files of different sequences.
pub fn numbered_frames(paths: &[PathBuf]) -> anyhow::Result<(String, Vec<(i64, PathBuf)>)> {
    let mut base: Option<String> = None;
    let mut frames = Vec::with_capacity(paths.len());
    for p in paths {
        let Some((b, n)) = numbered(p) else {
            anyhow::bail!(
                "{}: a frame of a sequence needs a frame number at the end of its name \
                 (scene_0001.lxs)",
                p.display()
            );
        };
        match &base {
            Some(first) if *first != b => anyhow::bail!(
                "{}: frames of one sequence share a name ({first:?}, not {b:?})",
                p.display()
            ),
            _ => base = Some(b),
        }
        frames.push((n, p.clone()));
    }
    frames.sort_by_key(|(n, _)| *n);
    if let Some(w) = frames.windows(2).find(|w| w[0].0 == w[1].0) {
        anyhow::bail!(
            "{} and {} are both frame {}",
            w[0].1.display(),
            w[1].1.display(),
            w[0].0
        );
    }
    Ok((base.unwrap_or_default(), frames))
}

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let rt = runtime()?;
    let header = pb::SubmitHeader {
        file_name: String::new(),
        name: a.name.clone().unwrap_or_default(),
        haltspp: a.haltspp,
        halttime: a.halttime,
        haltthreshold: a.haltthreshold,
        seed: a.seed,
        priority: a.priority,
        scene: a.scene_in_bundle.clone().unwrap_or_default(),
        frame: a.frame,
        sequence: String::new(),
        sequence_frame: None,
        tags: a.tags.clone(),
        min_memory_mb: a.min_memory_mb,
        max_workers: a.max_workers,
        webhook: a.webhook.clone().unwrap_or_default(),
    };
    let ids = match (a.scenes.as_slice(), a.frames) {
        ([scene], None) => {
            let upload = luxfarm_wire::bundle::prepare(scene)?;
            let h = pb::SubmitHeader {
                file_name: upload.file_name.clone(),
                ..header
            };
            let job = rt.block_on(submit(&a.remote, h, upload.bytes))?;
            println!("{}", job.id);
            eprintln!("{}", job_line(&job));
            vec![job.id]
        }
        ([scene], Some(range)) => {
            let base = a.name.clone().unwrap_or_else(|| stem(scene));
            let seq = rt.block_on(create_sequence(&a.remote, &base, &a.policy))?;
            let upload = luxfarm_wire::bundle::prepare(scene)?;
            let frames = range.frames().map(|f| (f, Some(f), upload.bytes.clone()));
            submit_frames(&rt, &a.remote, &seq, &header, &upload.file_name, frames)?
        }
        (scenes, None) => {
            let (base, frames) = numbered_frames(scenes)?;
            let base = a.name.clone().unwrap_or(base);
            let seq = rt.block_on(create_sequence(&a.remote, &base, &a.policy))?;
            let mut uploads = Vec::with_capacity(frames.len());
            for (n, path) in frames {
                let upload = luxfarm_wire::bundle::prepare(&path)?;
                uploads.push((n, upload));
            }
            let mut ids = Vec::new();
            for (n, upload) in uploads {
                let one = std::iter::once((n, None, upload.bytes));
                ids.extend(submit_frames(
                    &rt,
                    &a.remote,
                    &seq,
                    &header,
                    &upload.file_name,
                    one,
                )?);
            }
            ids
        }
        (_, Some(_)) => anyhow::bail!("--frames takes one animated scene, not several files"),
    };
    if !a.watch {
        return Ok(ExitCode::SUCCESS);
    }
    let mut code = ExitCode::SUCCESS;
    for id in &ids {
        if super::watch::watch_job(&rt, &a.remote, id)? != ExitCode::SUCCESS {
            code = ExitCode::from(1);
        }
    }
    Ok(code)
}

fn stem(scene: &Path) -> String {
    scene
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("scene")
        .to_string()
}

/// Submits the frames of a sequence: (frame number, animation frame, bundle) each; prints
/// each job's id and returns them.
fn submit_frames(
    rt: &tokio::runtime::Runtime,
    remote: &Remote,
    seq: &pb::SequenceInfo,
    header: &pb::SubmitHeader,
    file_name: &str,
    frames: impl Iterator<Item = (i64, Option<i64>, Vec<u8>)>,
) -> anyhow::Result<Vec<String>> {
    let mut ids = Vec::new();
    for (number, frame, bytes) in frames {
        let h = pb::SubmitHeader {
            file_name: file_name.to_string(),
            frame: frame.or(header.frame),
            sequence: seq.id.clone(),
            sequence_frame: Some(number),
            ..header.clone()
        };
        let job = rt.block_on(submit(remote, h, bytes))?;
        println!("{}", job.id);
        eprintln!("frame {number}: {}", job_line(&job));
        ids.push(job.id);
    }
    Ok(ids)
}

/// Creates a sequence on the master and prints its id.
async fn create_sequence(
    remote: &Remote,
    name: &str,
    policy: &str,
) -> anyhow::Result<pb::SequenceInfo> {
    let mut client = remote.jobs()?;
    let seq = client
        .create_sequence(pb::CreateSequenceRequest {
            name: name.to_string(),
            policy: policy.to_string(),
        })
        .await
        .map_err(status)?
        .into_inner();
    println!("sequence {}", seq.id);
    eprintln!("sequence {} ({}, {})", seq.name, seq.id, seq.policy);
    Ok(seq)
}

/// Streams a bundle to the master and returns the queued job.
pub async fn submit(
    remote: &Remote,
    header: pb::SubmitHeader,
    bytes: Vec<u8>,
) -> anyhow::Result<pb::JobInfo> {
    let mut chunks = vec![pb::SubmitChunk {
        part: Some(pb::submit_chunk::Part::Header(header)),
    }];
    for c in bytes.chunks(pb::CHUNK_BYTES) {
        chunks.push(pb::SubmitChunk {
            part: Some(pb::submit_chunk::Part::Data(c.to_vec())),
        });
    }
    let mut client = remote.jobs()?;
    let job = client
        .submit(tokio_stream::iter(chunks))
        .await
        .map_err(status)?
        .into_inner();
    Ok(job)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_numbers_come_from_file_names() {
        assert_eq!(
            numbered(Path::new("f/shot_0012.lxs")),
            Some(("shot".into(), 12))
        );
        assert_eq!(numbered(Path::new("a7.lxs")), Some(("a".into(), 7)));
        assert_eq!(numbered(Path::new("shot.lxs")), None);
        let paths: Vec<PathBuf> = ["s_0003.lxs", "s_0001.lxs", "s_0002.lxs"]
            .iter()
            .map(PathBuf::from)
            .collect();
        let (base, frames) = numbered_frames(&paths).unwrap();
        assert_eq!(base, "s");
        let numbers: Vec<i64> = frames.iter().map(|(n, _)| *n).collect();
        assert_eq!(numbers, [1, 2, 3]);
        let dup = [PathBuf::from("s_01.lxs"), PathBuf::from("s_1.lxs")];
        assert!(numbered_frames(&dup).is_err());
        let mixed = [PathBuf::from("a_1.lxs"), PathBuf::from("b_2.lxs")];
        assert!(numbered_frames(&mixed).is_err());
        assert!(numbered_frames(&[PathBuf::from("plain.lxs")]).is_err());
    }
}
