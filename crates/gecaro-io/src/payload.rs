//! Payloads as people write them (issue 38): `20kg`, or `20kg,0,0,120mm`
//! with its centre of mass in the tool frame n+1; in a study file also as a
//! table, `payload = { mass = "20kg", com = [0, 0, "120mm"] }`
//! ([`PayloadSpec`]).
//!
//! The mass takes `kg` or `g`; each coordinate of the centre takes `m`,
//! `mm` or `um`, and a bare number is in metres. gecaro works in kilograms
//! and metres ([`LinkMass`]).
//!
//! No trap on the way (issue 74): a bare number beside a coordinate that
//! carries its unit (`12kg,-32.3,17.3,-17.3mm`) is refused rather than read
//! as metres — only a bare 0 may stand there, being 0 in any unit; a centre
//! farther than [`MAX_PAYLOAD_CENTRE`] from the tool frame (`12kg,0,0,80`,
//! 80 m) and a mass beyond [`MAX_PAYLOAD_KG`] are refused with their value.
//! A mass beyond what the robot itself weighs is refused where the robot is
//! known (gecaro-app).

use gecaro_core::LinkMass;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::written_lengths::number_length;

/// The heaviest payload gecaro takes: 10 t, beyond any serial arm's — the
/// bound of a link's mass ([`gecaro_core::MAX_LINK_MASS`]), stated once.
pub const MAX_PAYLOAD_KG: f64 = gecaro_core::MAX_LINK_MASS;

/// The farthest a payload's centre of mass may be from the tool frame
/// (m): a 2 m tool is longer than any an arm carries, and a centre farther
/// is a length read in the wrong unit.
pub const MAX_PAYLOAD_CENTRE: f64 = 2.0;

/// Refuses a payload no arm carries: a mass beyond [`MAX_PAYLOAD_KG`] or
/// not finite and ≥ 0, a centre beyond [`MAX_PAYLOAD_CENTRE`] from the
/// tool frame or not finite.
///
/// # Errors
/// A sentence with the value and its bound.
pub fn check_payload(payload: &LinkMass) -> Result<(), String> {
    if !(payload.mass.is_finite() && (0.0..=MAX_PAYLOAD_KG).contains(&payload.mass)) {
        return Err(format!(
            "the payload's mass {} kg is not a mass from 0 to {MAX_PAYLOAD_KG} kg",
            payload.mass
        ));
    }
    let distance = payload.com.norm();
    if !(distance.is_finite() && distance <= MAX_PAYLOAD_CENTRE) {
        return Err(format!(
            "the payload's centre ({}, {}, {}) m is {distance} m from the tool frame, beyond \
             the {MAX_PAYLOAD_CENTRE} m of any tool: is it in mm (give its unit: 80mm)?",
            payload.com.x, payload.com.y, payload.com.z
        ));
    }
    Ok(())
}

/// A payload from its text (see the module docs).
///
/// # Errors
/// A sentence naming what is wrong: no unit on the mass, a unit of another
/// kind, a negative or absurd mass, a centre of other than three values,
/// a bare number beside a coordinate with its unit, a centre beyond
/// [`MAX_PAYLOAD_CENTRE`].
///
/// ```
/// let payload = gecaro_io::parse_payload("20kg,0,0,120mm").unwrap();
/// assert_eq!(payload.mass, 20.0);
/// assert!((payload.com.z - 0.12).abs() < 1e-15);
/// assert_eq!(gecaro_io::parse_payload("500g").unwrap().mass, 0.5);
/// assert!(gecaro_io::parse_payload("20").is_err());
/// // A bare number beside a unit, and a centre 80 m away, are refused.
/// assert!(gecaro_io::parse_payload("12kg,-32.3,17.3,-17.3mm").is_err());
/// assert!(gecaro_io::parse_payload("12kg,0,0,80").is_err());
/// assert!(gecaro_io::parse_payload("12kg,0,0,80mm").is_ok());
/// ```
pub fn parse_payload(text: &str) -> Result<LinkMass, String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let (mass_text, centre) = match parts.as_slice() {
        [mass] => (*mass, None),
        [mass, x, y, z] => (*mass, Some([*x, *y, *z])),
        _ => {
            return Err(format!(
                "'{text}' is not a payload: give its mass, and optionally its centre in the \
                 tool frame: 20kg or 20kg,0,0,120mm"
            ));
        }
    };
    let (number, unit) = mass_text.split_at(number_length(mass_text));
    let factor = match unit.trim() {
        "kg" => 1.0,
        "g" => 1e-3,
        "" => {
            return Err(format!(
                "the payload's mass '{mass_text}' needs its unit: kg or g"
            ));
        }
        other => {
            return Err(format!(
                "unknown mass unit '{other}' in '{mass_text}' (kg or g)"
            ));
        }
    };
    let mass = number
        .parse::<f64>()
        .map_err(|_| format!("the payload's mass '{mass_text}' is not a number"))?
        * factor;
    if !(mass.is_finite() && (0.0..=MAX_PAYLOAD_KG).contains(&mass)) {
        return Err(format!(
            "the payload's mass '{mass_text}' is not a mass from 0 to {MAX_PAYLOAD_KG} kg"
        ));
    }
    let com = match centre {
        None => Vector3::zeros(),
        Some(coordinates) => {
            let [x, y, z] = crate::written_lengths::point(&coordinates, "the payload's centre")?;
            Vector3::new(x, y, z)
        }
    };
    let payload = LinkMass { mass, com };
    check_payload(&payload)?;
    Ok(payload)
}

/// A payload as a study file states it: the text of [`parse_payload`], or
/// a table of its mass and centre. Written back as it was read; a table
/// with another key (`centre`) is refused by name, not ignored.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum PayloadSpec {
    /// `"20kg"` or `"20kg,0,0,120mm"`.
    Text(String),
    /// `{ mass = "20kg", com = [0, 0, "120mm"] }`: the centre's
    /// coordinates are lengths with their unit, or bare numbers in metres.
    Table {
        /// The mass, with its unit (`kg` or `g`; a bare number is refused).
        mass: Quantity,
        /// The centre of mass in the tool frame (the flange's axis by default).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        com: Option<[Quantity; 3]>,
    },
}

/// A value of a payload's table: a bare number, or a text with its unit.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(untagged)]
pub enum Quantity {
    /// A bare number: metres for a coordinate (a mass needs its unit).
    Number(f64),
    /// `"20kg"`, `"120mm"`.
    Text(String),
}

impl std::fmt::Display for Quantity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Quantity::Number(value) => write!(f, "{value}"),
            Quantity::Text(text) => f.write_str(text),
        }
    }
}

/// The table form's keys, and no other.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PayloadTable {
    mass: Quantity,
    #[serde(default)]
    com: Option<[Quantity; 3]>,
}

impl<'de> Deserialize<'de> for PayloadSpec {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Stated;
        impl<'de> serde::de::Visitor<'de> for Stated {
            type Value = PayloadSpec;

            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(
                    "a payload: \"20kg,0,0,120mm\" or { mass = \"20kg\", com = [0, 0, \"120mm\"] }",
                )
            }

            fn visit_str<E: serde::de::Error>(self, text: &str) -> Result<PayloadSpec, E> {
                Ok(PayloadSpec::Text(text.to_owned()))
            }

            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> Result<PayloadSpec, A::Error> {
                let table =
                    PayloadTable::deserialize(serde::de::value::MapAccessDeserializer::new(map))?;
                Ok(PayloadSpec::Table {
                    mass: table.mass,
                    com: table.com,
                })
            }
        }
        deserializer.deserialize_any(Stated)
    }
}

impl PayloadSpec {
    /// The payload stated (see [`parse_payload`]).
    ///
    /// # Errors
    /// As [`parse_payload`].
    pub fn payload(&self) -> Result<LinkMass, String> {
        match self {
            PayloadSpec::Text(text) => parse_payload(text),
            PayloadSpec::Table { mass, com } => {
                let mut text = mass.to_string();
                for coordinate in com.iter().flatten() {
                    text.push_str(&format!(",{coordinate}"));
                }
                parse_payload(&text)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_payloads_say_what_is_wrong() {
        for (text, expected) in [
            ("20", "needs its unit"),
            ("20lb", "unknown mass unit"),
            ("-1kg", "not a mass"),
            ("20kg,0,0", "not a payload"),
            ("20kg,0,0,1deg", "unknown length unit"),
            ("abckg", "unknown mass unit"),
            ("1e999kg", "not a mass"),
        ] {
            let message = parse_payload(text).expect_err(text);
            assert!(message.contains(expected), "{text}: {message}");
        }
        let payload = parse_payload(" 6kg , 0.1m , -20mm , 0 ").expect("valid");
        assert_eq!(payload.com, Vector3::new(0.1, -0.02, 0.0));
        let payload = parse_payload("6kg,0.1,-0.02,0").expect("bare metres");
        assert_eq!(payload.com, Vector3::new(0.1, -0.02, 0.0));
    }

    /// The traps of the trial (issue 74): a centre in mixed units, a centre
    /// 80 m away; an honest payload with zeros beside its unit reads.
    #[test]
    fn mixed_units_and_a_centre_out_of_reach_are_refused() {
        for (text, expected) in [
            (
                "12kg,-32.2959,17.2685,-17.3173mm",
                "mixes units: '-32.2959' has none",
            ),
            ("12kg,0,0.5,80mm", "mixes units: '0.5' has none"),
            ("12kg,0,0,80", "80 m from the tool frame"),
            ("12kg,2m,1m,0", "from the tool frame"),
        ] {
            let message = parse_payload(text).expect_err(text);
            assert!(message.contains(expected), "{text}: {message}");
        }
        let honest = parse_payload("12kg,0,0,80mm").expect("honest");
        assert!((honest.com - Vector3::new(0.0, 0.0, 0.08)).norm() < 1e-15);
        assert!(
            check_payload(&LinkMass {
                mass: 1e300,
                com: Vector3::zeros()
            })
            .is_err()
        );
    }

    /// A study's table states what the text does, and reads back as written.
    #[test]
    fn a_payload_table_is_its_text() {
        #[derive(Deserialize, Serialize)]
        struct Set {
            payload: PayloadSpec,
        }
        for (table, text) in [
            (
                "payload = { mass = \"20kg\", com = [0, \"10mm\", \"120mm\"] }",
                "20kg,0,10mm,120mm",
            ),
            ("payload = { mass = \"500g\" }", "500g"),
            ("payload = \"6kg,0,0,50mm\"", "6kg,0,0,50mm"),
        ] {
            let set: Set = toml::from_str(table).expect(table);
            assert_eq!(set.payload.payload(), parse_payload(text), "{table}");
            let written = toml::to_string(&set).expect("written");
            let again: Set = toml::from_str(&written).expect("read back");
            assert_eq!(again.payload, set.payload, "{written}");
        }
        let set: Set = toml::from_str("payload = { mass = 20 }").expect("a bare mass reads");
        let message = set.payload.payload().expect_err("a bare mass");
        assert!(message.contains("needs its unit"), "{message}");
        for (table, expected) in [
            ("payload = { mass = \"2kg\", com = [0, 0] }", "length 3"),
            (
                "payload = { mass = \"2kg\", centre = [0, 0, 0] }",
                "unknown field `centre`",
            ),
            ("payload = 20", "a payload"),
        ] {
            let message = toml::from_str::<Set>(table).err().expect(table).to_string();
            assert!(message.contains(expected), "{table}: {message}");
        }
        let json: Set = serde_json::from_str(r#"{"payload": {"mass": "2kg"}}"#).expect("json");
        assert_eq!(json.payload.payload().expect("2 kg").mass, 2.0);
    }
}
