//! What a URDF may hold before it is parsed: a streaming pass over the XML
//! (quick-xml, constant memory) bounds its nesting depth and its numbers of
//! elements, links and joints, so that a hostile or broken file (5,000
//! nested elements, 100,000 joints) is refused with a message instead of
//! overflowing the parser's stack or allocating without end.
//!
//! The bounds are far above real robots: a URDF nests 4–6 levels deep, and
//! the largest robot descriptions (humanoids with hands) have a few hundred
//! links.

/// Deepest nesting of elements.
pub(crate) const MAX_DEPTH: usize = 64;
/// Most `<link>` elements, and most `<joint>` elements.
pub(crate) const MAX_LINKS: usize = 2_000;
/// Most elements of any kind.
pub(crate) const MAX_ELEMENTS: usize = 200_000;

/// Where a bound is exceeded: the byte offset and what is wrong. Malformed
/// XML is left to the parser, which names the line.
pub(crate) fn check(text: &str) -> Result<(), (usize, String)> {
    use quick_xml::events::Event;
    let mut reader = quick_xml::Reader::from_str(text);
    let (mut depth, mut elements, mut links, mut joints) = (0usize, 0usize, 0usize, 0usize);
    loop {
        let offset = usize::try_from(reader.buffer_position()).unwrap_or(0);
        let element = match reader.read_event() {
            Ok(Event::Start(element)) => {
                depth += 1;
                if depth > MAX_DEPTH {
                    return Err((
                        offset,
                        format!(
                            "elements nested more than {MAX_DEPTH} deep: not a robot description \
                             (a URDF nests a few levels)"
                        ),
                    ));
                }
                element
            }
            Ok(Event::Empty(element)) => element,
            Ok(Event::End(_)) => {
                depth = depth.saturating_sub(1);
                continue;
            }
            Ok(Event::Eof) | Err(_) => return Ok(()),
            Ok(_) => continue,
        };
        elements += 1;
        // Only the robot's own <link> and <joint> (depth 2) are counted:
        // <joint> also names a mimic's or a transmission's joint inside.
        let own = depth <= 2;
        match element.name().as_ref() {
            b"link" if own => links += 1,
            b"joint" if own => joints += 1,
            _ => {}
        }
        let too_many = if elements > MAX_ELEMENTS {
            Some(format!("more than {MAX_ELEMENTS} elements"))
        } else if links > MAX_LINKS {
            Some(format!("more than {MAX_LINKS} links"))
        } else if joints > MAX_LINKS {
            Some(format!("more than {MAX_LINKS} joints"))
        } else {
            None
        };
        if let Some(what) = too_many {
            return Err((
                offset,
                format!("{what}: beyond any robot gecaro imports; import the arm's own URDF"),
            ));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deep_or_huge_files_are_refused_and_robots_pass() {
        let deep = format!(
            "<robot name=\"r\">{}{}</robot>",
            "<a>".repeat(5_000),
            "</a>".repeat(5_000)
        );
        assert!(check(&deep).is_err_and(|(_, message)| message.contains("nested")));
        let many = format!(
            "<robot name=\"r\">{}</robot>",
            "<link name=\"l\"/>".repeat(MAX_LINKS + 1)
        );
        assert!(check(&many).is_err_and(|(_, message)| message.contains("links")));
        let robot = "<robot name=\"r\"><link name=\"a\"><visual><geometry><box size=\"1 1 1\"/>\
                     </geometry></visual></link><joint name=\"j\" type=\"revolute\"><parent \
                     link=\"a\"/><child link=\"b\"/><mimic joint=\"k\"/></joint><link \
                     name=\"b\"/></robot>";
        assert_eq!(check(robot), Ok(()));
    }
}
