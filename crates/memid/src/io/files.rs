//! Output files that never overwrite an input and are written whole or not at all.
//!
//! * **Inputs** are recorded by device and inode ([`Inputs`]), so a hard link, a symbolic link
//!   or a path like `out/../model.ron` cannot disguise one.
//! * **An output path** is resolved through its longest existing ancestor — nothing is created
//!   before the check — and the rest of its components are applied lexically, which is what the
//!   kernel does once the missing directories exist (`nodir/../model.ron` is `model.ron`). If the
//!   resolved file exists and is an input, the command is refused with one line naming both.
//! * **Writing** ([`Outputs`]): every output of a command is staged first — a temporary file in
//!   the target's own directory (`.NAME.tmp-PID-N`), registered for removal — and the stage is
//!   committed at the end by renaming each temporary onto its target. A regular file is thus
//!   replaced whole or not at all. A target that exists and is not a regular file (a device, a
//!   FIFO, a terminal) is written in place and never renamed onto. `-` is standard output.
//! * **Cleanup**: temporaries are removed on every error path (the stage's `Drop`) and on
//!   SIGINT/SIGTERM (a signal thread removes the registered files and exits with 128 + signal).

use anyhow::{Context, Result, anyhow, bail};
use std::collections::HashSet;
use std::io::Write;
use std::os::unix::fs::MetadataExt;
use std::path::{Component, Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Temporary files that exist now, removed by the signal thread if the process is interrupted.
static TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
static COUNTER: AtomicUsize = AtomicUsize::new(0);

fn register(path: &Path) {
    if let Ok(mut list) = TEMPORARIES.lock() {
        list.push(path.to_path_buf());
    }
}

fn unregister(path: &Path) {
    if let Ok(mut list) = TEMPORARIES.lock() {
        list.retain(|p| p != path);
    }
}

/// Starts the thread that removes staged temporaries on SIGINT or SIGTERM and exits with
/// 128 + the signal's number.
pub fn install_signal_cleanup() {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) else { return };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            if let Ok(list) = TEMPORARIES.lock() {
                for path in list.iter() {
                    let _ = std::fs::remove_file(path);
                }
            }
            std::process::exit(128 + signal);
        }
    });
}

/// The identity of a file: (device, inode).
type FileId = (u64, u64);

fn identity(path: &Path) -> Option<FileId> {
    std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()))
}

/// `path` made absolute: its longest existing prefix canonicalised (symbolic links followed),
/// the remaining components applied lexically.
pub fn resolve(path: &Path) -> PathBuf {
    let absolute = if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir().unwrap_or_else(|_| PathBuf::from("/")).join(path)
    };
    let mut resolved = PathBuf::from("/");
    let mut exists = true;
    for component in absolute.components() {
        match component {
            Component::RootDir | Component::Prefix(_) => resolved = PathBuf::from("/"),
            Component::CurDir => {}
            Component::ParentDir => {
                resolved.pop();
            }
            Component::Normal(name) => {
                let next = resolved.join(name);
                if exists && std::fs::symlink_metadata(&next).is_ok() {
                    resolved = std::fs::canonicalize(&next).unwrap_or(next);
                } else {
                    exists = false;
                    resolved = next;
                }
            }
        }
    }
    resolved
}

/// The files a command reads, so that no output replaces one of them.
#[derive(Default)]
pub struct Inputs {
    files: Vec<(PathBuf, FileId)>,
}

impl Inputs {
    /// Records an input (a file that does not exist is not recorded: reading it fails with its
    /// own message).
    pub fn add(&mut self, path: &Path) {
        if let Some(id) = identity(path) {
            self.files.push((path.to_path_buf(), id));
        }
    }

    /// Fails if `output` (resolved as described in the module docs) is one of the inputs.
    pub fn guard(&self, output: &Path) -> Result<()> {
        let resolved = resolve(output);
        if let Some(id) = identity(&resolved)
            && let Some((input, _)) = self.files.iter().find(|(_, f)| *f == id)
        {
            bail!(
                "refusing to overwrite the input {} with the output {}; choose another output path",
                input.display(),
                output.display()
            );
        }
        Ok(())
    }
}

/// Where an output goes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Target {
    /// Standard output (`-`).
    Stdout,
    /// A file.
    File(PathBuf),
}

impl Target {
    /// `-` is standard output, anything else a file.
    pub fn from_arg(path: &Path) -> Self {
        if path.as_os_str() == "-" { Target::Stdout } else { Target::File(path.to_path_buf()) }
    }
}

/// One staged output.
enum Staged {
    /// Bytes for standard output.
    Stdout(Vec<u8>),
    /// A complete temporary file to rename onto its target.
    Renamed { temporary: PathBuf, target: PathBuf },
    /// Bytes for a target that is not a regular file (written in place).
    InPlace { target: PathBuf, bytes: Vec<u8> },
}

/// The outputs of one command, staged and committed together.
pub struct Outputs<'a> {
    inputs: &'a Inputs,
    staged: Vec<Staged>,
    targets: HashSet<PathBuf>,
}

impl<'a> Outputs<'a> {
    /// An empty stage guarded against `inputs`.
    pub fn new(inputs: &'a Inputs) -> Self {
        Self { inputs, staged: Vec::new(), targets: HashSet::new() }
    }

    /// Checks a target before any work is done: not an input, not a directory, not named twice.
    pub fn check(&mut self, target: &Target) -> Result<()> {
        let Target::File(path) = target else { return Ok(()) };
        self.inputs.guard(path)?;
        let resolved = resolve(path);
        if resolved.is_dir() {
            bail!("{} is a directory; give a file name", path.display());
        }
        if path.file_name().is_none() {
            bail!("{} is not a file path", path.display());
        }
        if !self.targets.insert(resolved) {
            bail!("{} is named as two outputs; give each output its own file", path.display());
        }
        Ok(())
    }

    /// Checks a report directory: it must be a directory or not exist yet.
    pub fn check_directory(&self, dir: &Path) -> Result<()> {
        let resolved = resolve(dir);
        if resolved.exists() && !resolved.is_dir() {
            bail!("--report {}: exists and is not a directory; give a directory", dir.display());
        }
        Ok(())
    }

    /// Stages `bytes` for `target`.
    pub fn stage(&mut self, target: &Target, bytes: Vec<u8>) -> Result<()> {
        match target {
            Target::Stdout => {
                self.staged.push(Staged::Stdout(bytes));
                Ok(())
            }
            Target::File(path) => self.stage_file(path, "", |tmp| {
                std::fs::write(tmp, &bytes).with_context(|| format!("cannot write {}", tmp.display()))
            }),
        }
    }

    /// Stages a file that `write` produces at a temporary path ending in `suffix` (an encoder
    /// that picks its format from the extension needs it).
    pub fn stage_file(
        &mut self,
        path: &Path,
        suffix: &str,
        write: impl FnOnce(&Path) -> Result<()>,
    ) -> Result<()> {
        self.inputs.guard(path)?;
        let resolved = resolve(path);
        if let Ok(meta) = std::fs::metadata(&resolved)
            && !meta.file_type().is_file()
        {
            if meta.is_dir() {
                bail!("{} is a directory; give a file name", path.display());
            }
            // A device, FIFO or socket: produce the bytes, write them in place at commit.
            let temporary = self.temporary(&std::env::temp_dir().join("memid"), suffix);
            register(&temporary);
            let result = write(&temporary).and_then(|()| {
                std::fs::read(&temporary).with_context(|| format!("cannot read {}", temporary.display()))
            });
            let _ = std::fs::remove_file(&temporary);
            unregister(&temporary);
            self.staged.push(Staged::InPlace { target: path.to_path_buf(), bytes: result? });
            return Ok(());
        }
        let dir = resolved.parent().map(Path::to_path_buf).unwrap_or_else(|| PathBuf::from("/"));
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("cannot create the directory {}", dir.display()))?;
        let name = resolved.file_name().ok_or_else(|| anyhow!("{} is not a file path", path.display()))?;
        let temporary = self.temporary(&dir.join(format!(".{}", name.to_string_lossy())), suffix);
        register(&temporary);
        if let Err(e) = write(&temporary) {
            let _ = std::fs::remove_file(&temporary);
            unregister(&temporary);
            return Err(e);
        }
        self.staged.push(Staged::Renamed { temporary, target: resolved });
        Ok(())
    }

    fn temporary(&self, base: &Path, suffix: &str) -> PathBuf {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        PathBuf::from(format!("{}.tmp-{}-{n}{suffix}", base.display(), std::process::id()))
    }

    /// Writes everything: renames the temporaries onto their targets, writes in place, prints.
    ///
    /// # Errors
    /// The first failure, naming its path; what was not yet committed is removed.
    pub fn commit(mut self) -> Result<()> {
        let staged = std::mem::take(&mut self.staged);
        let mut rest = staged.into_iter();
        while let Some(item) = rest.next() {
            let result = match &item {
                Staged::Stdout(bytes) => print_bytes(bytes),
                Staged::Renamed { temporary, target } => std::fs::rename(temporary, target)
                    .with_context(|| format!("cannot move the result into {}", target.display())),
                Staged::InPlace { target, bytes } => std::fs::OpenOptions::new()
                    .write(true)
                    .open(target)
                    .and_then(|mut f| f.write_all(bytes))
                    .with_context(|| format!("cannot write {}", target.display())),
            };
            if let Staged::Renamed { temporary, .. } = &item {
                unregister(temporary);
            }
            if let Err(e) = result {
                if let Staged::Renamed { temporary, .. } = &item {
                    let _ = std::fs::remove_file(temporary);
                }
                self.staged = rest.collect();
                return Err(e);
            }
        }
        Ok(())
    }
}

impl Drop for Outputs<'_> {
    fn drop(&mut self) {
        for item in &self.staged {
            if let Staged::Renamed { temporary, .. } = item {
                let _ = std::fs::remove_file(temporary);
                unregister(temporary);
            }
        }
    }
}

/// A write to standard output failed because the reader went away: the program ends quietly.
#[derive(Debug, thiserror::Error)]
#[error("standard output was closed")]
pub struct BrokenPipe;

/// Writes to standard output: a closed pipe becomes [`BrokenPipe`] (ended quietly by `main`),
/// any other failure (a full device) an error that says so.
pub fn print_bytes(bytes: &[u8]) -> Result<()> {
    let mut out = std::io::stdout().lock();
    match out.write_all(bytes).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Err(BrokenPipe.into()),
        Err(e) => Err(anyhow!("cannot write to standard output: {e}")),
    }
}

/// [`print_bytes`] for text.
pub fn print(text: &str) -> Result<()> {
    print_bytes(text.as_bytes())
}
