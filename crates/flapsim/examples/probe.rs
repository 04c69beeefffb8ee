fn main() {
    for name in ["drosophila", "bumblebee", "robobee"] {
        let v = flapsim::Vehicle::from_toml(flapsim::builtin_model(name).unwrap(), name).unwrap();
        let t0 = std::time::Instant::now();
        match flapsim::stability::analyze(&v, true) {
            Ok(r) => {
                println!(
                    "{name}: trim amp {:+.2} deg mean {:+.2} deg pitch {:.2} deg resid {:.2e} ({:?})",
                    r.trim.controls.amplitude_rad.to_degrees(),
                    r.trim.controls.mean_stroke_rad.to_degrees(),
                    r.trim.pitch_rad.to_degrees(),
                    r.trim.max_residual(),
                    t0.elapsed()
                );
                for m in &r.longitudinal_modes {
                    println!(
                        "  lon {} re {:.3} im {:.3} T {:?} t½/2 {:?}",
                        m.description,
                        m.re_per_s,
                        m.im_rad_s,
                        m.period_s,
                        m.time_to_half_or_double_s
                    );
                }
                for m in &r.lateral_modes {
                    println!(
                        "  lat {} re {:.3} im {:.3}",
                        m.description, m.re_per_s, m.im_rad_s
                    );
                }
                for f in &r.floquet_longitudinal {
                    println!("  floquet exp {:.3} {:.3}", f.exponent.0, f.exponent.1);
                }
            }
            Err(e) => println!("{name}: {e}"),
        }
    }
}
