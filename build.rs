//! Build script: records the git commit the crate is built from (`VERGEN_GIT_SHA`, short
//! form, through `vergen-gitcl`), which the header of every generated file names beside the
//! version (`emit::COMMIT`). Built outside a git checkout (a source archive), the variable is
//! absent or vergen's placeholder, and the header says `commit unknown`.
use vergen_gitcl::{Emitter, GitclBuilder};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let git = GitclBuilder::default().sha(true).build()?;
    Emitter::default().add_instructions(&git)?.emit()?;
    Ok(())
}
