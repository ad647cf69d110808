//! The chain's three job scripts (docs/farm.md): plain bash with
//! `#SBATCH` lines, each value in them read by bash and `sbatch` as the
//! one value it is ([`super::values`]), each job leaving a node it
//! failed on behind.
//!
//! A job that fails is submitted again by its own script, in bash, to
//! another node: a node whose lmfilm is broken cannot be trusted to run
//! lmfilm to say so. Every failed attempt is kept as a file
//! `farm/failed/STAGE@NODE@JOB` (its exit code and log), every later job
//! as `farm/retries/STAGE@JOB`; `farm status` reads both.

use super::values::{sbatch_log, shell_quote, Memory, SlurmName, WallTime};
use crate::film::names::FARM_DIR;

/// The chain's logs, inside its farm folder.
pub const LOGS_DIR: &str = "logs";
/// Failed attempts, one empty-named file each: `STAGE@NODE@JOB`.
pub const FAILED_DIR: &str = "failed";
/// Jobs submitted after the first three: `STAGE@JOB`.
pub const RETRIES_DIR: &str = "retries";
/// The first three jobs' ids, a line `STAGE ID` each.
pub const JOBS_FILE: &str = "jobs.txt";

/// Attempts of one stage (the derivation, one shard, the finish) before
/// the chain gives it up.
pub const ATTEMPTS: u32 = 3;
/// Failed jobs after which a node is left out of every later attempt of
/// the chain (a stage is never tried again where it failed once).
pub const NODE_FAILURES: u32 = 2;

/// What every job asks Slurm for, each value checked.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Request {
    pub partition: Option<SlurmName>,
    pub time: Option<WallTime>,
    pub mem: Option<Memory>,
    pub cpus: Option<u32>,
    pub account: Option<SlurmName>,
}

/// The command words each job runs, already quoted for bash: the
/// binary, the scenes, and each stage's options.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Commands {
    pub lmfilm: String,
    pub scenes: Vec<String>,
    pub derive: Vec<String>,
    pub render: Vec<String>,
    pub sound: Vec<String>,
}

/// The three job scripts of a chain.
#[derive(Debug, Clone, PartialEq)]
pub struct Chain {
    pub derive: String,
    pub render: String,
    pub finish: String,
}

/// The scripts' file names in the farm folder.
pub const SCRIPTS: [&str; 3] = ["derive.sh", "render.sh", "finish.sh"];

/// `template` with each `@KEY@` replaced by its value, in one pass: a
/// value is never read again for keys (a folder named `@BIN@` stays
/// itself).
fn fill(template: &str, values: &[(&str, &str)]) -> String {
    let mut out = String::with_capacity(template.len() * 2);
    let mut rest = template;
    while let Some(at) = rest.find('@') {
        out.push_str(&rest[..at]);
        let after = &rest[at + 1..];
        let key = after
            .find('@')
            .map(|end| &after[..end])
            .and_then(|k| values.iter().find(|(name, _)| *name == k));
        match key {
            Some((name, value)) => {
                out.push_str(value);
                rest = &after[name.len() + 1..];
            }
            None => {
                out.push('@');
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// What every script does before its stage: the folder, the node, and
/// `again`, which sends a failed job to another node.
const PROLOGUE: &str = r#"set -uo pipefail
# The film's folder (on storage every node shares) and the node here.
dir=@DIR@
farm="$dir/@FARM@"
node="${SLURMD_NODENAME:-$HOSTNAME}"
[[ $node =~ ^[A-Za-z0-9._-]+$ ]] || node=unknown

# avoid STAGE: sets $exclude to the nodes a new attempt of STAGE must
# not run on, joined by commas (those where STAGE failed, counted in
# $tries, and those that failed @NODE_FAILURES@ jobs of this chain), from the
# failures kept as farm/@FAILED@/STAGE@NODE@JOB.
avoid() {
  local f base n
  local -A fails=() skip=()
  tries=0
  for f in "$farm/@FAILED@"/*@*@*; do
    [ -f "$f" ] || continue
    base=${f##*/}
    n=${base#*@}
    n=${n%@*}
    fails[$n]=$((${fails[$n]:-0} + 1))
    if [ "${base%%@*}" = "$1" ]; then
      tries=$((tries + 1))
      skip[$n]=1
    fi
  done
  for n in "${!fails[@]}"; do
    if [ "${fails[$n]}" -ge @NODE_FAILURES@ ]; then skip[$n]=1; fi
  done
  exclude="${!skip[*]}"
  exclude=${exclude// /,}
}

# again STAGE CODE [SBATCH OPTION...]: this job failed here with exit
# CODE. The failure is kept, and the job submitted again to another node
# (`avoid`), STAGE tried @ATTEMPTS@ times at most. Prints the new job's id.
again() {
  local stage=$1 code=$2 id
  shift 2
  [ -n "${SLURM_JOB_ID:-}" ] || return 1 # run by hand, not by Slurm
  mkdir -p "$farm/@FAILED@" "$farm/@RETRIES@" &&
    printf 'exit %s\nlog %s\n' "$code" "$log" >"$farm/@FAILED@/$stage@$node@$SLURM_JOB_ID" ||
    return 1
  avoid "$stage"
  if [ "$tries" -ge @ATTEMPTS@ ]; then
    echo "lmfilm-farm: $stage failed $tries times (on $exclude): no attempt left" >&2
    return 1
  fi
  if ! id=$(sbatch --parsable --exclude="$exclude" "$@" "$script") || [[ ! ${id%%;*} =~ ^[0-9]+$ ]]; then
    echo "lmfilm-farm: $stage found no other node (sbatch --exclude=$exclude refused)" >&2
    return 1
  fi
  id=${id%%;*}
  : >"$farm/@RETRIES@/$stage@$id"
  echo "lmfilm-farm: $stage failed on $node (exit $code); attempt $((tries + 1)) of @ATTEMPTS@ is job $id, not on $exclude" >&2
  echo "$id"
}
"#;

const DERIVE: &str = r#"script="$farm/derive.sh"
log="$farm/@LOGS@/derive-${SLURM_JOB_ID:-0}.out"

# job STAGE: the id of the chain's first STAGE job (farm/@JOBS@).
job() {
  local stage id
  [ -f "$farm/@JOBS@" ] || return 1
  while read -r stage id; do
    if [ "$stage" = "$1" ]; then echo "$id" && return 0; fi
  done <"$farm/@JOBS@"
  return 1
}

echo "lmfilm-derive: node $node, job ${SLURM_JOB_ID:-none}"
@BIN@ derive @SCENES@ -o "$dir"@OPTIONS@ && exit 0
code=$?
if id=$(again derive "$code"); then
  # The render tasks wait for the new attempt instead.
  render=$(job render) && scontrol update JobId="$render" Dependency="afterok:$id"
fi
exit "$code"
"#;

const RENDER: &str = r#"[[ ${SLURM_ARRAY_TASK_ID:-} =~ ^[0-9]+$ ]] || { echo "lmfilm-render: SLURM_ARRAY_TASK_ID is not a task number" >&2; exit 2; }
task=$SLURM_ARRAY_TASK_ID
script="$farm/render.sh"
log="$farm/@LOGS@/render-${SLURM_ARRAY_JOB_ID:-0}_$task.out"

# Task i renders shard i/@SHARDS@: the frames still missing of it.
echo "lmfilm-render: shard $task/@SHARDS@, node $node, job ${SLURM_JOB_ID:-none}"
@BIN@ render "$dir" --shard "$task/@SHARDS@" --log-frames@OPTIONS@ && exit 0
code=$?
again "render-$task" "$code" --array="$task" >/dev/null
exit "$code"
"#;

const FINISH: &str = r#"script="$farm/finish.sh"
log="$farm/@LOGS@/finish-${SLURM_JOB_ID:-0}.out"
echo "lmfilm-finish: node $node, job ${SLURM_JOB_ID:-none}"

# Shards sent to other nodes and still queued: this job goes again
# after them.
waiting=
for f in "$farm/@RETRIES@"/render-*@*; do
  [ -f "$f" ] || continue
  if [ -z "${queued+set}" ]; then
    queued=$'\n'$(squeue -h -o %F)$'\n' || { echo "lmfilm-finish: squeue did not answer" >&2; exit 1; }
  fi
  if [[ $queued == *$'\n'"${f##*@}"$'\n'* ]]; then waiting+=":${f##*@}"; fi
done
if [ -n "$waiting" ]; then
  avoid finish
  id=$(sbatch --parsable ${exclude:+--exclude="$exclude"} --dependency="afterany$waiting" "$script") || exit 1
  id=${id%%;*}
  [[ $id =~ ^[0-9]+$ ]] && : >"$farm/@RETRIES@/finish@$id"
  waiting=${waiting#:}
  echo "lmfilm-finish: shards still to come (jobs ${waiting//:/ }): finishing after them as job $id"
  exit 0
fi

# The frames a shard left (none when every shard rendered its own), the
# soundtrack and manifest, the MP4, and the check.
finish() {
  @BIN@ render "$dir" --log-frames@RENDER_OPTIONS@ &&
    @BIN@ sound "$dir"@OPTIONS@ &&
    @BIN@ mux "$dir" &&
    @BIN@ verify "$dir"
}
finish && exit 0
code=$?
again finish "$code" >/dev/null
exit "$code"
"#;

impl Request {
    /// The `#SBATCH` lines of a job: its name, its log (in the film
    /// folder `dir`, as `sbatch` reads it), the array, then the request.
    fn header(&self, name: &str, dir: &str, log: &str, array: Option<u32>) -> String {
        let mut lines = vec![
            "#!/bin/bash -p".to_string(),
            format!("#SBATCH --job-name=lmfilm-{name}"),
            format!(
                "#SBATCH --output={}",
                sbatch_log(dir, &format!("{FARM_DIR}/{LOGS_DIR}/{log}"))
            ),
        ];
        let mut option = |k: &str, v: String| lines.push(format!("#SBATCH --{k}={v}"));
        if let Some(n) = array {
            option("array", format!("1-{n}"));
        }
        if let Some(p) = &self.partition {
            option("partition", p.as_str().to_string());
        }
        if let Some(t) = &self.time {
            option("time", t.to_string());
        }
        if let Some(m) = &self.mem {
            option("mem", m.to_string());
        }
        if let Some(c) = self.cpus {
            option("cpus-per-task", c.to_string());
        }
        if let Some(a) = &self.account {
            option("account", a.as_str().to_string());
        }
        lines.join("\n") + "\n"
    }

    /// The chain's scripts over the film folder `dir` (absolute, UTF-8,
    /// checked by `values::folder_path`) in `shards` render tasks.
    pub fn chain(&self, dir: &str, shards: u32, commands: &Commands) -> Chain {
        let words =
            |o: &[String]| -> String { o.iter().map(|w| format!(" {}", shell_quote(w))).collect() };
        let (n, attempts, node_failures) = (
            shards.to_string(),
            ATTEMPTS.to_string(),
            NODE_FAILURES.to_string(),
        );
        let (derive_opts, render_opts, sound_opts) = (
            words(&commands.derive),
            words(&commands.render),
            words(&commands.sound),
        );
        let folder = shell_quote(dir);
        let scenes = commands
            .scenes
            .iter()
            .map(|s| shell_quote(s))
            .collect::<Vec<_>>()
            .join(" ");
        let bin = shell_quote(&commands.lmfilm);
        let script = |name: &str, log: &str, array: Option<u32>, body: &str, options: &str| {
            let values = [
                ("DIR", folder.as_str()),
                ("FARM", FARM_DIR),
                ("LOGS", LOGS_DIR),
                ("FAILED", FAILED_DIR),
                ("RETRIES", RETRIES_DIR),
                ("JOBS", JOBS_FILE),
                ("ATTEMPTS", attempts.as_str()),
                ("NODE_FAILURES", node_failures.as_str()),
                ("SHARDS", n.as_str()),
                ("BIN", bin.as_str()),
                ("SCENES", scenes.as_str()),
                ("OPTIONS", options),
                ("RENDER_OPTIONS", render_opts.as_str()),
            ];
            format!(
                "{}{}\n{}",
                self.header(name, dir, log, array),
                fill(PROLOGUE, &values),
                fill(body, &values)
            )
        };
        Chain {
            derive: script("derive", "derive-%j.out", None, DERIVE, &derive_opts),
            render: script(
                "render",
                "render-%A_%a.out",
                Some(shards),
                RENDER,
                &render_opts,
            ),
            finish: script("finish", "finish-%j.out", None, FINISH, &sound_opts),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_template_is_filled_once() {
        let t = "a=@A@ b=@B@ @C@ x@y";
        assert_eq!(
            fill(t, &[("A", "'@B@'"), ("B", "2")]),
            "a='@B@' b=2 @C@ x@y"
        );
    }
}
