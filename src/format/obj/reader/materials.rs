//! `usemtl` and `mtllib`: material names numbered as they appear, material libraries
//! read, and the names resolved into materials at the end.

use rayon::prelude::*;

use super::Reader;
use super::messages::{NAMELESS_USEMTL, push_warning};
use crate::error::Result;
use crate::format::mtl;
use crate::format::obj::lines::{self, decode_name, shown};

impl Reader<'_, '_> {
    /// `usemtl` followed by `name` (trimmed): the material of the faces that follow.
    pub(super) fn use_material(&mut self, name: &[u8], line: usize) {
        if name.is_empty() {
            self.warn(line, NAMELESS_USEMTL);
            self.material = None;
            return;
        }
        let id = self.material_id(decode_name(name));
        self.material = Some(id);
        self.usemtl_lines.push((id, line));
    }

    /// The number of a `usemtl` name, in order of first appearance.
    pub(super) fn material_id(&mut self, name: String) -> u32 {
        let next_id = self.material_names.len() as u32;
        let id = *self.material_ids.entry(name.clone()).or_insert(next_id);
        if id == next_id {
            self.material_names.push(name);
        }
        id
    }

    /// `mtllib` followed by `rest` (trimmed).
    pub(super) fn material_libraries(&mut self, rest: &[u8], line: usize) -> Result<()> {
        if rest.is_empty() {
            self.warn(line, "mtllib without a file name");
        }
        for name in library_names(rest) {
            self.read_library(&name, line)?;
        }
        Ok(())
    }

    fn read_library(&mut self, name: &[u8], line: usize) -> Result<()> {
        let Some(read) = self.options.read_library.as_mut() else {
            return Ok(());
        };
        let path = self.folder.join(decode_name(name));
        if !self.libraries_read.insert(path.clone()) {
            return Ok(());
        }
        let bytes = match read(&path) {
            Ok(bytes) => bytes,
            Err(e) => {
                self.warn(
                    line,
                    format!("material library skipped, its materials are unknown: {e}"),
                );
                return Ok(());
            }
        };
        let library = mtl::parse(&bytes, &path)?;
        for warning in library.warnings {
            push_warning(
                &mut self.obj.warnings,
                &mut self.suppressed_warnings,
                warning.path,
                warning.line,
                warning.message,
            );
        }
        for (kind, count) in library.skipped {
            *self.obj.skipped.entry(format!("mtl:{kind}")).or_insert(0) += count;
        }
        for material in library.materials {
            if let Some(&first) = self.material_index.get(&material.name) {
                let first = &self.obj.materials[first as usize];
                let message = format!(
                    "material {} is defined again: the first definition ({}:{}) is kept",
                    shown(material.name.as_bytes()),
                    first.path.display(),
                    first.line
                );
                push_warning(
                    &mut self.obj.warnings,
                    &mut self.suppressed_warnings,
                    material.path.clone(),
                    material.line,
                    message,
                );
                continue;
            }
            let index = self.obj.materials.len() as u32;
            self.material_index.insert(material.name.clone(), index);
            self.obj.materials.push(material);
        }
        Ok(())
    }

    /// Turns the `usemtl` names on the triangles into material indices; an unknown
    /// name gives a warning at each `usemtl` naming it and no material.
    pub(super) fn resolve_materials(&mut self) {
        if self.material_names.is_empty() {
            return; // no triangle names one
        }
        let resolved: Vec<Option<u32>> = self
            .material_names
            .iter()
            .map(|name| self.material_index.get(name).copied())
            .collect();
        for (id, line) in std::mem::take(&mut self.usemtl_lines) {
            if resolved[id as usize].is_none() {
                let message = format!(
                    "usemtl names material {}, which no material library defines: its \
                     faces get the default material",
                    shown(self.material_names[id as usize].as_bytes())
                );
                self.warn(line, message);
            }
        }
        self.obj.triangles.par_iter_mut().for_each(|t| {
            t.material = t.material.and_then(|id| resolved[id as usize]);
        });
    }
}

/// The file names of an `mtllib` line: separated by white space, with `\ ` standing for
/// a space inside a name.
fn library_names(rest: &[u8]) -> Vec<Vec<u8>> {
    let mut names = Vec::new();
    let mut name = Vec::new();
    let mut bytes = rest.iter().copied().peekable();
    while let Some(b) = bytes.next() {
        if b == b'\\' && bytes.peek() == Some(&b' ') {
            name.push(b' ');
            bytes.next();
        } else if lines::is_space(b) {
            if !name.is_empty() {
                names.push(std::mem::take(&mut name));
            }
        } else {
            name.push(b);
        }
    }
    if !name.is_empty() {
        names.push(name);
    }
    names
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn library_names_split_on_unescaped_spaces() {
        let names = library_names(br"a.mtl  my\ lib\ 2.mtl	c\d.mtl");
        assert_eq!(
            names,
            [
                b"a.mtl".to_vec(),
                b"my lib 2.mtl".to_vec(),
                br"c\d.mtl".to_vec()
            ]
        );
    }
}
