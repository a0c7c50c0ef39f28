//! Hostile input: random program texts and random register images never panic, and what is
//! accepted comes back unchanged (text → steps → text, words → steps → words).

use fun147::{Fun147, Inputs, MemPlc, Plc, Program, Reg, Relay, SimAxes, assemble, disassemble};

const SEED: &str = "001 SPD 5000\n LIN ADR,500,400,300,200,Ut\n WAIT TIME,100\n GOTO NEXT\n002 SPD R1000\n LIN ADR,D100,D200, , ,Ut\n WAIT TIME,R500\n GOTO NEXT\n003 SPD R1002\n LIN ADR,0,0,R300,R400,Ps\n WAIT X0\n GOTO 1\n";

#[rustfmt::skip]
const PIECES: &[&str] = &[
    "001 ", "002 ", "003 ", "SPD ", "LIN ", "LINE ", "WAIT ", "EXT ", "GOTO ", "MEND", "ADR,", "ABS,", "TIME,",
    "NEXT", ",", ", ", "Ut", "Ps", "R1000", "D100", "R3839", "X0", "M1912", "S999", "5000", "-1", "−", "，", "；",
    "; c", "\n", "\n ", "0", "1999999", "2000000", "99999999999", "\t", "é", "線", "", " ",
];

/// Random sequences of the language's pieces and stray characters, and the example program
/// with pieces of it replaced, inserted or removed.
#[test]
fn random_text_never_panics() {
    let mut rng = fastrand::Rng::with_seed(0x9E37_79B9_7F4A_7C15);
    let mut accepted = 0;
    for _ in 0..20_000 {
        let mut text = String::new();
        for _ in 0..rng.usize(..40) {
            if rng.usize(..10) == 0 {
                text.push(char::from_u32(rng.usize(..0x3000) as u32).unwrap_or('?'));
            } else {
                let piece = PIECES[rng.usize(..PIECES.len())];
                text.push_str(piece);
            }
        }
        if rng.usize(..2) == 0 {
            let mut mutated = SEED.to_owned();
            for _ in 0..1 + rng.usize(..3) {
                let at = (0..=mutated.len())
                    .filter(|&i| mutated.is_char_boundary(i))
                    .nth(rng.usize(..mutated.len()))
                    .unwrap_or(0);
                let end = (at..=mutated.len())
                    .find(|&i| i >= at + rng.usize(..4) && mutated.is_char_boundary(i))
                    .unwrap_or(at);
                let piece = PIECES[rng.usize(..PIECES.len())];
                mutated.replace_range(at..end, piece);
            }
            text = mutated;
        }
        if let Ok(program) = assemble(&text) {
            accepted += 1;
            assert_eq!(assemble(&disassemble(&program)).as_ref(), Ok(&program), "{text:?}");
            assert_eq!(Program::from_words(&program.to_words()).as_ref(), Ok(&program));
        }
    }
    assert!(accepted > 100, "some random texts are programs: {accepted}");
}

/// Random images (the example with random words changed, and random words throughout) decode
/// without panicking; an accepted one encodes back to the same words.
#[test]
fn random_images_never_panic() {
    let mut rng = fastrand::Rng::with_seed(0xD1B5_4A32_D192_ED03);
    let seed = assemble(SEED).unwrap().to_words();
    let mut accepted = 0;
    for round in 0..50_000 {
        let mut words = if round % 2 == 0 { seed.clone() } else { (0..47).map(|_| rng.u64(..) as u16).collect() };
        for _ in 0..1 + rng.usize(..3) {
            let i = rng.usize(..words.len());
            words[i] = match rng.usize(..3) {
                0 => rng.u64(..) as u16,
                1 => words[i] ^ (1 << rng.usize(..16)),
                _ => [0, 1, 0xFFFF, 0x930F, 0xA55C, 3, 3839, 4000, 8071][rng.usize(..9)],
            };
        }
        words.truncate(rng.usize(..60).max(40));
        if let Ok(program) = Program::from_words(&words) {
            accepted += 1;
            let n = program.steps.len();
            assert_eq!(program.to_words(), words[..2 + 15 * n], "decoding is exact");
        }
    }
    assert!(accepted > 500, "{accepted}");
}

/// The instruction on random images, random register contents and random inputs: no panic,
/// and once EN is off and the axes at rest every Ready flag is back ON.
#[test]
fn random_runs_never_panic() {
    let mut rng = fastrand::Rng::with_seed(0x0123_4567_89AB_CDEF);
    let seed = assemble(SEED).unwrap().to_words();
    for _ in 0..300 {
        let mut plc = MemPlc::new();
        let mut axes = SimAxes::new();
        let sr = Reg::D(2000);
        for (i, word) in seed.iter().enumerate() {
            let word = if rng.usize(..30) == 0 { rng.u64(..) as u16 } else { *word };
            plc.set_word(Reg::D(2000 + i as u16), word);
        }
        for reg in [Reg::R(1000), Reg::R(1002), Reg::D(100), Reg::D(200), Reg::R(300), Reg::R(400), Reg::R(500)] {
            plc.set_dword(reg, if rng.usize(..2) == 0 { rng.u64(..) as i32 } else { rng.usize(..3000) as i32 });
        }
        let mut fun = Fun147::new(rng.usize(..2) as u8, sr, Reg::D(3000)).unwrap();
        let mut en = false;
        for _ in 0..2000 {
            if rng.usize(..200) == 0 {
                en = !en;
            }
            let inputs = Inputs { en, pau: rng.usize(..300) == 0, abt: rng.usize(..1000) == 0 };
            plc.set_relay(Relay::X(0), rng.usize(..50) == 0);
            plc.set_relay(Relay::M(1991), rng.usize(..2) == 0);
            if rng.usize(..500) == 0 {
                plc.set_word(Reg::D(3000), rng.u64(..) as u16);
            }
            fun.step(&mut plc, &mut axes, inputs, 0.001);
            axes.advance(0.001);
        }
        plc.set_relay(Relay::M(1991), false);
        fun.step(&mut plc, &mut axes, Inputs::default(), 0.001);
        assert!((1992..=1995).all(|m| plc.relay(Relay::M(m))));
    }
}
