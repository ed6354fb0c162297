use super::*;

#[test]
fn footers_that_do_not_decode_say_why() {
    let good = encode_footer(&Footer {
        final_tick: 3,
        final_hash: 4,
        diverged: None,
    });
    assert_eq!(decode_footer(&good).map(|f| f.final_tick), Ok(3));
    assert_eq!(
        decode_footer(&good[..20]),
        Err(DecodeError::Truncated { len: 20 })
    );
    let mut long = good.to_vec();
    long.extend_from_slice(&[0, 0]);
    assert_eq!(decode_footer(&long), Err(DecodeError::TrailingBytes(2)));
    let mut bad = good;
    bad[16] = 2;
    assert_eq!(decode_footer(&bad), Err(DecodeError::DivergenceFlag(2)));
    bad[16] = 1;
    bad[33] = 9;
    assert_eq!(decode_footer(&bad), Err(DecodeError::DivergenceCause(9)));
}

/// Every variant prints the message it printed when these errors were strings.
#[test]
fn error_messages_are_pinned() {
    let cases: [(DecodeError, &str); 11] = [
        (
            DecodeError::Truncated { len: 20 },
            "payload ends at byte 20",
        ),
        (DecodeError::TrailingBytes(2), "2 unread bytes at the end"),
        (DecodeError::ArrayTooLong, "array too long"),
        (
            DecodeError::DivergenceCause(9),
            "unknown divergence cause 9",
        ),
        (
            DecodeError::DivergenceFlag(2),
            "divergence flag 2, expected 0 or 1",
        ),
        (DecodeError::IntegratorTag(7), "unknown integrator tag 7"),
        (
            DecodeError::MaskOrCarry {
                mask: 0x400,
                carry: 0,
                launch: 4,
            },
            "force mask 0x400, carry flag 0 or flags 4 out of range",
        ),
        (
            DecodeError::UndeclaredForce(ForceKind::Spring),
            "force term Spring is active but not declared",
        ),
        (
            DecodeError::BodyCount {
                bodies: 3,
                len: 115,
            },
            "3 bodies do not fit a 115 byte keyframe",
        ),
        (DecodeError::IdsNotIncreasing, "body ids are not increasing"),
        (
            DecodeError::Tally(1 << 32),
            "an event count of 4294967296, past a u32",
        ),
    ];
    for (error, message) in cases {
        assert_eq!(error.to_string(), message, "{error:?}");
    }
}
