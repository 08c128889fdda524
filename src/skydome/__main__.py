from skydome.cli.main import run

run()
